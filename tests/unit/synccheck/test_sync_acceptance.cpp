// Issue 18's acceptance on simulated clocks: offset 3.2 ms, drift 40 ppm, jitter 150 µs, 1 % dropped
// frames over 60 s at 30 Hz → offset within 20 µs, drift within 2 ppm, jitter std within 10 %, every
// drop counted exactly, for several seeds.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "vifusion/synccheck/analyse.hpp"
#include "vifusion/synccheck/clock_model.hpp"

namespace vifusion::synccheck {
namespace {

constexpr double kOffsetToleranceNs = 20'000.0;
constexpr double kDriftTolerancePpm = 2.0;
constexpr double kJitterToleranceFraction = 0.10;

TEST(SynccheckAcceptance, DefaultModelIsTheIssuesCase) {
  const ClockModel model;
  EXPECT_EQ(model.offset_ns, 3'200'000);
  EXPECT_EQ(model.drift_ppm, 40.0);
  EXPECT_EQ(model.jitter_ns, 150'000);
  EXPECT_EQ(model.drop_probability, 0.01);
  EXPECT_EQ(model.duration_s, 60.0);
  EXPECT_EQ(model.frame_rate_hz, 30.0);
}

class SynccheckAcceptanceSeeds : public ::testing::TestWithParam<std::uint64_t> {};

TEST_P(SynccheckAcceptanceSeeds, OffsetDriftJitterAndDropsAreMeasured) {
  const ClockModel model;
  SimulationTruth truth;
  const SyncInput input = simulate(model, GetParam(), &truth);
  const SyncReport report = analyse(input);
  const StreamStats* stream = report.stream(kFrameMinusEdge);
  ASSERT_NE(stream, nullptr);

  const double offset_error_ns = stream->offset_at_first_ns - model.expectedOffsetNs();
  const double drift_error_ppm = stream->drift_ppm - model.drift_ppm;
  const double jitter_error = stream->jitter_std_ns / model.expectedJitterStdNs() - 1.0;
  std::printf(
      "seed %llu: offset %.1f us (error %+.2f us), drift %.3f ppm (error %+.3f), jitter std %.2f us "
      "(error %+.2f %%), drops %llu of %zu true (edges %zu, numbers %llu)\n",
      static_cast<unsigned long long>(GetParam()), stream->offset_at_first_ns * 1e-3, offset_error_ns * 1e-3,
      stream->drift_ppm, drift_error_ppm, stream->jitter_std_ns * 1e-3, jitter_error * 100.0,
      static_cast<unsigned long long>(report.dropped.dropped), truth.dropped_frames, report.dropped.edges_without_frame,
      static_cast<unsigned long long>(report.dropped.frame_number_gaps));

  EXPECT_LT(std::abs(offset_error_ns), kOffsetToleranceNs);
  EXPECT_LT(std::abs(drift_error_ppm), kDriftTolerancePpm);
  EXPECT_LT(std::abs(jitter_error), kJitterToleranceFraction);
  EXPECT_GT(truth.dropped_frames, 0u);  // the seed really drops frames
  EXPECT_EQ(report.dropped.edges_without_frame, truth.dropped_frames);
  EXPECT_EQ(report.dropped.frame_number_gaps, truth.dropped_frames);
  EXPECT_EQ(report.dropped.dropped, truth.dropped_frames);

  // Every delivered frame paired, none twice; the mean sits where the drift puts the middle of the run.
  EXPECT_EQ(report.frames.count, truth.strobes - truth.dropped_frames);
  EXPECT_EQ(report.frames.paired_with_edge, report.frames.count);
  EXPECT_EQ(report.frames.without_edge, 0u);
  EXPECT_EQ(report.duplicated.frames_on_one_edge, 0u);
  const double mid_run_s = 0.5 * model.duration_s;
  EXPECT_NEAR(stream->offset_mean_ns, model.expectedOffsetNs() + model.drift_ppm * 1e3 * mid_run_s, 20'000.0);
  // The other streams: the device event is the stamp here; the kernel's own offset is known too.
  const StreamStats* event = report.stream(kDeviceEventMinusEdge);
  EXPECT_EQ(event->count, stream->count);
  EXPECT_DOUBLE_EQ(event->offset_at_first_ns, stream->offset_at_first_ns);
  const StreamStats* kernel = report.stream(kKernelMinusEdge);
  EXPECT_NEAR(kernel->offset_at_first_ns,
              static_cast<double>(model.kernel_offset_ns - model.edge_latency_ns - model.edge_latency_spread_ns),
              40'000.0);                     // 250 µs kernel jitter: ~12 µs standard error
  EXPECT_NEAR(kernel->drift_ppm, 0.0, 3.0);  // kernel stamps are host time: no mapping, no drift
  EXPECT_NEAR(report.imu.rate_hz, model.imu_rate_hz, 0.1);
  EXPECT_EQ(report.imu.gaps, 0u);
  EXPECT_NEAR(report.clock_residuals.mean_ns, static_cast<double>(model.mapper_latency_mean_ns), 30'000.0);
  EXPECT_TRUE(report.passed) << report.toJson();
}

INSTANTIATE_TEST_SUITE_P(Seeds, SynccheckAcceptanceSeeds, ::testing::Values(1u, 2u, 3u, 4u, 5u, 6u, 7u, 8u));

}  // namespace
}  // namespace vifusion::synccheck
