// Pass/fail against the limits: the acceptance case passes the ZR300 defaults; a bad clock fails and
// names what failed; no data fails without crashing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "vifusion/synccheck/analyse.hpp"
#include "vifusion/synccheck/clock_model.hpp"

namespace vifusion::synccheck {
namespace {

const CheckResult* findCheck(const SyncReport& report, const std::string& name) {
  for (const CheckResult& check : report.checks) {
    if (check.name == name) return &check;
  }
  return nullptr;
}

TEST(SynccheckChecks, EveryCheckIsReportedWithItsLimit) {
  const SyncReport report = analyse(simulate(ClockModel{}, 31));
  const std::vector<std::string> expected{"offset", "jitter", "drift", "dropped", "frame_rate", "imu_rate", "imu_gap"};
  ASSERT_EQ(report.checks.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(report.checks[i].name, expected[i]);
  const SyncCheckOptions defaults;
  EXPECT_EQ(findCheck(report, "offset")->limit, 5e6);  // one IMU period at 200 Hz
  EXPECT_EQ(findCheck(report, "jitter")->limit, 1e6);
  EXPECT_EQ(findCheck(report, "drift")->limit, 50.0);
  EXPECT_EQ(findCheck(report, "imu_gap")->limit, 20e6);
  EXPECT_EQ(findCheck(report, "dropped")->limit, defaults.max_dropped_fraction);
  EXPECT_NEAR(findCheck(report, "offset")->value, report.stream(kFrameMinusEdge)->offset_median_ns, 1e-6);
  EXPECT_TRUE(report.passed);
  EXPECT_TRUE(report.failedChecks().empty());
}

// A mapping that does not follow the device clock (-120 ppm) and a jittery event path (600 µs std):
// drift and jitter fail, by name; the rest passes (the median offset, 3.2 - 3.6 ms, too).
TEST(SynccheckChecks, ABadClockFailsAndNamesTheChecks) {
  ClockModel model;
  model.drift_ppm = -120.0;
  model.jitter_ns = 600'000;
  const SyncReport report = analyse(simulate(model, 32));
  EXPECT_FALSE(report.passed);
  EXPECT_EQ(report.failedChecks(), (std::vector<std::string>{"jitter", "drift"}));
  const CheckResult* drift = findCheck(report, "drift");
  EXPECT_NEAR(drift->value, 120.0, 5.0);
  EXPECT_EQ(drift->unit, "ppm");
  EXPECT_NE(drift->detail.find("exceeds limit 50"), std::string::npos) << drift->detail;
  EXPECT_GT(findCheck(report, "jitter")->value, 1e6);  // p99 of |N(0, 600 µs)| = 1.55 ms
}

TEST(SynccheckChecks, ManyDropsFailTheDroppedCheck) {
  ClockModel model;
  model.drop_probability = 0.08;
  SimulationTruth truth;
  const SyncReport report = analyse(simulate(model, 33, &truth));
  EXPECT_EQ(report.failedChecks(), std::vector<std::string>{"dropped"});
  EXPECT_NEAR(report.dropped.fraction, static_cast<double>(truth.dropped_frames) / truth.strobes, 1e-12);
}

TEST(SynccheckChecks, AWrongFrameRateFails) {
  ClockModel model;
  model.frame_rate_hz = 60.0;
  SyncCheckOptions options;  // expects 30 Hz
  const SyncReport report = analyse(simulate(model, 34), options);
  EXPECT_EQ(report.failedChecks(), std::vector<std::string>{"frame_rate"});
  EXPECT_NEAR(findCheck(report, "frame_rate")->value, 1.0, 0.01);  // 60 Hz is 100 % off
}

TEST(SynccheckChecks, NoDataFailsEveryCheckWithoutACrash) {
  const SyncReport report = analyse(SyncInput{});
  EXPECT_FALSE(report.passed);
  EXPECT_EQ(report.failedChecks().size(), report.checks.size());
  EXPECT_EQ(findCheck(report, "offset")->detail, "no frame paired with a sync edge");
  EXPECT_TRUE(std::isnan(report.stream(kFrameMinusEdge)->offset_median_ns));
  EXPECT_EQ(report.frames.count, 0u);
}

// Frames without any sync line: the edge checks fail, the frame and IMU ones still judge.
TEST(SynccheckChecks, NoEdgesFailsOnlyTheEdgeChecks) {
  SyncInput input = simulate(ClockModel{}, 35);
  input.edges.clear();
  const SyncReport report = analyse(input);
  EXPECT_EQ(report.failedChecks(), (std::vector<std::string>{"offset", "jitter", "drift"}));
  EXPECT_EQ(report.frames.without_edge, report.frames.count);
  // Drops still come from the device frame numbers.
  EXPECT_GT(report.dropped.frame_number_gaps, 0u);
  EXPECT_EQ(report.dropped.dropped, report.dropped.frame_number_gaps);
  EXPECT_EQ(report.stream(kFrameMinusKernel)->count, report.frames.count);
}

TEST(SynccheckChecks, ImuIsOptionalOnlyWhenSaidSo) {
  SyncInput input = simulate(ClockModel{}, 36);
  input.imu_t_ns.clear();
  EXPECT_EQ(analyse(input).failedChecks(), (std::vector<std::string>{"imu_rate", "imu_gap"}));
  SyncCheckOptions camera_only;
  camera_only.require_imu = false;
  const SyncReport report = analyse(input, camera_only);
  EXPECT_TRUE(report.passed);
  EXPECT_EQ(report.checks.size(), 5u);
}

}  // namespace
}  // namespace vifusion::synccheck
