// Bad input is counted and named in the report, never thrown and never a crash: time going backwards
// (frames, edges, IMU), NaN residuals, device counters stepping back, wrapping 12-bit counters.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "vifusion/synccheck/analyse.hpp"
#include "vifusion/synccheck/clock_model.hpp"

namespace vifusion::synccheck {
namespace {

bool mentions(const SyncReport& report, const std::string& text) {
  for (const std::string& problem : report.problems) {
    if (problem.find(text) != std::string::npos) return true;
  }
  return false;
}

TEST(SynccheckBadInput, FrameTimeGoingBackwardsIsCountedAndNamed) {
  ClockModel model;
  model.drop_probability = 0.0;
  SyncInput input = simulate(model, 41);
  // 12 ms before frame 499's stamp: more than the pairing window (8.3 ms) from any edge's prediction.
  input.frames[500].t_ns -= 12 * kNsPerMillisecond + model.framePeriodNs();
  const SyncReport report = analyse(input);
  EXPECT_EQ(report.frames.out_of_order, 1u);
  EXPECT_TRUE(mentions(report, "frame 500 (index 500): t_ns goes backwards by")) << report.toJson();
  EXPECT_EQ(report.frames.without_edge, 1u);
  EXPECT_EQ(report.dropped.edges_without_frame, 1u);  // its own edge saw no frame in time
  EXPECT_EQ(report.dropped.frame_number_gaps, 0u);    // though the counter says it came
}

TEST(SynccheckBadInput, EdgesOutOfOrderAreDroppedAndNamed) {
  ClockModel model;
  model.drop_probability = 0.0;
  SyncInput input = simulate(model, 42);
  input.edges[400].t_ns = input.edges[398].t_ns - 1;  // a rising edge (sequence 400) behind the previous one
  const SyncReport report = analyse(input);
  EXPECT_EQ(report.edges.out_of_order, 1u);
  EXPECT_EQ(report.edges.used, report.edges.count / 2 - 1);
  EXPECT_TRUE(mentions(report, "edge 400 (sequence 400): t_ns goes backwards"));
  EXPECT_EQ(report.frames.without_edge, 1u);
}

TEST(SynccheckBadInput, ImuTimeGoingBackwardsIsCounted) {
  SyncInput input = simulate(ClockModel{}, 43);
  std::swap(input.imu_t_ns[1000], input.imu_t_ns[1001]);
  input.imu_t_ns[2000] = input.imu_t_ns[1999];
  const SyncReport report = analyse(input);
  EXPECT_EQ(report.imu.out_of_order, 2u);
  EXPECT_TRUE(mentions(report, "IMU sample 1001: time goes backwards by"));
  EXPECT_TRUE(mentions(report, "IMU sample 2000: time repeats"));
  EXPECT_NEAR(report.imu.rate_hz, 200.0, 0.1);
}

TEST(SynccheckBadInput, NonFiniteResidualsAreCountedNotUsed) {
  SyncInput input = simulate(ClockModel{}, 44);
  const std::size_t total = input.clock_residuals.size();
  input.clock_residuals[3].residual_ns = std::numeric_limits<double>::quiet_NaN();
  input.clock_residuals[9].residual_ns = std::numeric_limits<double>::infinity();
  const SyncReport report = analyse(input);
  EXPECT_EQ(report.clock_residuals.non_finite, 2u);
  EXPECT_EQ(report.clock_residuals.samples, total - 2);
  EXPECT_TRUE(std::isfinite(report.clock_residuals.mean_ns));
  EXPECT_TRUE(mentions(report, "clock residual 3 (t_ns"));
}

TEST(SynccheckBadInput, ACounterSteppingBackIsNotADrop) {
  ClockModel model;
  model.drop_probability = 0.0;
  SyncInput input = simulate(model, 45);
  for (std::size_t i = 900; i < input.frames.size(); ++i) input.frames[i].device_frame_number -= 500;  // restart
  const SyncReport report = analyse(input);
  EXPECT_EQ(report.frames.frame_number_backwards, 1u);
  EXPECT_EQ(report.dropped.frame_number_gaps, 0u);
  EXPECT_TRUE(mentions(report, "frame 900 (index 900): device_frame_number 1400 is behind the previous 1899"));
}

// The motion module's 12-bit numbers wrap at 4096: no gap, no step back, the drops still exact.
TEST(SynccheckBadInput, TwelveBitCountersWrap) {
  ClockModel model;
  model.first_frame_number = 4000;
  SimulationTruth truth;
  SyncInput input = simulate(model, 46, &truth);
  for (CameraFrameTimes& frame : input.frames) frame.device_frame_number %= 4096;
  SyncCheckOptions options;
  options.frame_number_bits = 12;
  const SyncReport report = analyse(input, options);
  EXPECT_EQ(report.frames.frame_number_backwards, 0u);
  EXPECT_EQ(report.dropped.frame_number_gaps, truth.dropped_frames);
}

TEST(SynccheckBadInput, ProblemNotesAreCapped) {
  SyncInput input = simulate(ClockModel{}, 47);
  for (std::size_t i = 0; i + 1 < input.imu_t_ns.size(); i += 2) std::swap(input.imu_t_ns[i], input.imu_t_ns[i + 1]);
  const SyncReport report = analyse(input);
  EXPECT_GT(report.imu.out_of_order, 1000u);
  EXPECT_EQ(report.problems.size(), 20u);
}

}  // namespace
}  // namespace vifusion::synccheck
