#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "vifusion/synccheck/analyse.hpp"
#include "vifusion/synccheck/clock_model.hpp"
#include "vifusion/synccheck/sync_check_options.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion::synccheck {
namespace {

void expectInvalid(const std::function<void(SyncCheckOptions&)>& change, const std::string& expected) {
  SyncCheckOptions options;
  change(options);
  test::expectError([&] { options.validate(); }, expected);
  test::expectError([&] { analyse(SyncInput{}, options); }, expected);  // analyse validates too
}

void expectInvalidModel(const std::function<void(ClockModel&)>& change, const std::string& expected) {
  ClockModel model;
  change(model);
  test::expectError([&] { model.validate(); }, expected);
  test::expectError([&] { simulate(model, 1); }, expected);
}

TEST(SynccheckOptions, DefaultsAreValidAndFromTheZr300) {
  const SyncCheckOptions options;
  EXPECT_NO_THROW(options.validate());
  EXPECT_EQ(options.expected_frame_rate_hz, 30.0);
  EXPECT_EQ(options.expected_imu_rate_hz, 200.0);
  EXPECT_EQ(options.framePeriodNs(), 33'333'333);
  EXPECT_EQ(options.max_imu_gap_ns, 20'000'000);
  EXPECT_EQ(options.edge_polarity, EdgePolarity::kRising);
}

TEST(SynccheckOptions, EachBadFieldIsNamed) {
  expectInvalid([](auto& o) { o.expected_frame_rate_hz = 0.0; }, "'expected_frame_rate_hz' = 0 must be");
  expectInvalid([](auto& o) { o.expected_frame_rate_hz = std::nan(""); }, "'expected_frame_rate_hz' = nan");
  expectInvalid([](auto& o) { o.expected_imu_rate_hz = 2e5; }, "'expected_imu_rate_hz' = 200000 must be");
  expectInvalid([](auto& o) { o.edge_polarity = static_cast<EdgePolarity>(7); }, "'edge_polarity' = 7");
  expectInvalid([](auto& o) { o.frame_number_bits = 33; }, "'frame_number_bits' = 33 must be in [4, 32]");
  expectInvalid([](auto& o) { o.pairing_window_fraction = 0.5; }, "'pairing_window_fraction' = 0.5");
  expectInvalid([](auto& o) { o.max_abs_offset_ns = -1; }, "'max_abs_offset_ns' = -1 must be >= 0");
  expectInvalid([](auto& o) { o.max_jitter_p99_ns = -1; }, "'max_jitter_p99_ns' = -1 must be >= 0");
  expectInvalid([](auto& o) { o.max_abs_drift_ppm = -2.0; }, "'max_abs_drift_ppm' = -2 must be");
  expectInvalid([](auto& o) { o.max_dropped_fraction = 1.5; }, "'max_dropped_fraction' = 1.5 must be");
  expectInvalid([](auto& o) { o.max_imu_gap_ns = 0; }, "'max_imu_gap_ns' = 0 must be > 0");
  expectInvalid([](auto& o) { o.max_rate_error_fraction = 0.0; }, "'max_rate_error_fraction' = 0 must be");
}

TEST(SynccheckOptions, PolarityNamesRoundTrip) {
  for (EdgePolarity p : {EdgePolarity::kRising, EdgePolarity::kFalling}) {
    EXPECT_EQ(parseEdgePolarity(edgePolarityName(p)), p);
  }
  EXPECT_FALSE(parseEdgePolarity("both").has_value());
}

TEST(SynccheckClockModel, DefaultsAreValid) {
  const ClockModel model;
  EXPECT_NO_THROW(model.validate());
  EXPECT_EQ(model.expectedOffsetNs(), 3'180'000.0);
  EXPECT_NEAR(model.expectedJitterStdNs(), 150'083.3, 0.1);
}

TEST(SynccheckClockModel, EachBadFieldIsNamed) {
  expectInvalidModel([](auto& m) { m.frame_rate_hz = -1.0; }, "'frame_rate_hz' = -1 must be");
  expectInvalidModel([](auto& m) { m.duration_s = 0.05; }, "'duration_s' = 0.05 must be long enough for 2 strobes");
  expectInvalidModel([](auto& m) { m.start_ns = 0; }, "'start_ns' = 0 must be > 0");
  expectInvalidModel([](auto& m) { m.offset_ns = 17'000'000; },
                     "'offset_ns' = 17000000 must be within +-16666666 (half a frame period)");
  expectInvalidModel([](auto& m) { m.drift_ppm = 5000.0; }, "'drift_ppm' = 5000 must be finite and within +-1000");
  expectInvalidModel([](auto& m) { m.jitter_ns = -1; }, "'jitter_ns' = -1 must be >= 0");
  expectInvalidModel([](auto& m) { m.edge_latency_ns = -1; }, "'edge_latency_ns' = -1");
  expectInvalidModel([](auto& m) { m.edge_latency_spread_ns = -1; }, "'edge_latency_spread_ns' = -1");
  expectInvalidModel([](auto& m) { m.strobe_width_ns = 0; }, "'strobe_width_ns' = 0 must be in (0, 33333333)");
  expectInvalidModel([](auto& m) { m.drop_probability = 0.6; }, "'drop_probability' = 0.6 must be");
  expectInvalidModel([](auto& m) { m.duplicate_probability = -0.1; }, "'duplicate_probability' = -0.1");
  expectInvalidModel([](auto& m) { m.event_probability = 1.1; }, "'event_probability' = 1.1");
  expectInvalidModel([](auto& m) { m.kernel_offset_ns = -20'000'000; }, "'kernel_offset_ns' = -20000000");
  expectInvalidModel([](auto& m) { m.kernel_jitter_ns = -5; }, "'kernel_jitter_ns' = -5");
  expectInvalidModel([](auto& m) { m.device_origin_ns = -1; }, "'device_origin_ns' = -1");
  expectInvalidModel([](auto& m) { m.device_skew_ppm = std::nan(""); }, "'device_skew_ppm' = nan");
  expectInvalidModel([](auto& m) { m.imu_rate_hz = 0.0; }, "'imu_rate_hz' = 0 must be");
  expectInvalidModel([](auto& m) { m.imu_jitter_ns = -1; }, "'imu_jitter_ns' = -1");
  expectInvalidModel([](auto& m) { m.mapper_latency_mean_ns = -1; }, "'mapper_latency_mean_ns' = -1");
}

TEST(SynccheckClockModel, TheSameSeedGivesTheSameInput) {
  const ClockModel model;
  SimulationTruth a_truth, b_truth;
  const SyncInput a = simulate(model, 9, &a_truth);
  const SyncInput b = simulate(model, 9, &b_truth);
  ASSERT_EQ(a.frames.size(), b.frames.size());
  for (std::size_t i = 0; i < a.frames.size(); ++i) EXPECT_EQ(a.frames[i].t_ns, b.frames[i].t_ns);
  EXPECT_EQ(a.imu_t_ns, b.imu_t_ns);
  EXPECT_EQ(a_truth.dropped_frames, b_truth.dropped_frames);
  EXPECT_NE(simulate(model, 10).frames[5].t_ns, a.frames[5].t_ns);
  // What the model says: 1800 strobes, two edges each, 200 Hz IMU for 60 s, a residual per 4 samples.
  EXPECT_EQ(a_truth.strobes, 1800u);
  EXPECT_EQ(a.edges.size(), 3600u);
  EXPECT_NEAR(static_cast<double>(a.imu_t_ns.size()), 12'000.0, 2.0);
  EXPECT_EQ(a.clock_residuals.size(), a.imu_t_ns.size() / 4);
}

}  // namespace
}  // namespace vifusion::synccheck
