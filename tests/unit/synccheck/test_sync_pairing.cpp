// Pairing under what breaks "the nearest edge": negative offsets, offsets near half a frame period that
// drift across it, duplicated frames, the other edge polarity, kernel-stamped frames, lost edges; and IMU
// gaps.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "vifusion/synccheck/analyse.hpp"
#include "vifusion/synccheck/clock_model.hpp"

namespace vifusion::synccheck {
namespace {

constexpr double kOffsetToleranceNs = 20'000.0;
constexpr double kDriftTolerancePpm = 2.0;

/// Runs `model` and checks offset, drift and that every delivered frame paired with its own edge.
SyncReport expectMeasured(const ClockModel& model, std::uint64_t seed, SyncCheckOptions options = {},
                          double offset_tolerance_ns = kOffsetToleranceNs) {
  SimulationTruth truth;
  const SyncReport report = analyse(simulate(model, seed, &truth), options);
  const StreamStats* stream = report.stream(kFrameMinusEdge);
  EXPECT_NEAR(stream->offset_at_first_ns, model.expectedOffsetNs(), offset_tolerance_ns);
  EXPECT_NEAR(stream->drift_ppm, model.drift_ppm, kDriftTolerancePpm);
  EXPECT_EQ(report.frames.without_edge, 0u);
  EXPECT_EQ(report.dropped.edges_without_frame, truth.dropped_frames);
  EXPECT_EQ(report.dropped.frame_number_gaps, truth.dropped_frames);
  return report;
}

TEST(SynccheckPairing, NegativeOffset) {
  ClockModel model;
  model.offset_ns = -9'700'000;
  model.drift_ppm = -25.0;
  expectMeasured(model, 21);
}

// 16.3 ms with +40 ppm: the offset reaches 16.3 + 2.4 = 18.7 ms after 60 s, beyond half the period
// (16.67 ms), where the nearest edge is the NEXT strobe's. The tracked pairing follows it.
TEST(SynccheckPairing, OffsetNearHalfAPeriodDriftingAcrossIt) {
  ClockModel model;
  model.offset_ns = 16'300'000;
  const SyncReport report = expectMeasured(model, 22);
  const StreamStats* stream = report.stream(kFrameMinusEdge);
  const auto [low, high] = std::minmax_element(stream->offset_ns.begin(), stream->offset_ns.end());
  EXPECT_GT(*high, 18'000'000.0);  // beyond half a period: paired with its own edge anyway
  EXPECT_GT(*low, 15'000'000.0);   // and no frame paired one period off
}

// 150 ppm walks the offset 9 ms in 60 s, more than the pairing window (8.3 ms) around the first frames'
// offset: only pairing that follows the drift keeps every frame on its own edge.
TEST(SynccheckPairing, DriftWalkingFurtherThanThePairingWindow) {
  ClockModel model;
  model.offset_ns = 16'300'000;
  model.drift_ppm = 150.0;
  const SyncReport report = expectMeasured(model, 30);
  EXPECT_GT(report.stream(kFrameMinusEdge)->offset_ns.back(), 25'000'000.0);  // 3/4 of a period
}

TEST(SynccheckPairing, NegativeOffsetNearHalfAPeriodDriftingAcrossIt) {
  ClockModel model;
  model.offset_ns = -16'500'000;
  model.drift_ppm = -40.0;
  expectMeasured(model, 23);
}

// Jitter straddling ± half a period from the start: the nearest-edge differences split into two clusters
// 33 ms apart; their circular mean does not.
TEST(SynccheckPairing, OffsetAtHalfAPeriodWithJitterAcrossIt) {
  ClockModel model;
  model.offset_ns = 16'600'000;
  model.drift_ppm = 0.0;
  model.jitter_ns = 400'000;
  // 400 µs jitter: the offset's standard error is 2·400/√1800 = 19 µs, so 20 µs is ~1σ here; 3σ instead.
  expectMeasured(model, 24, {}, 60'000.0);
}

TEST(SynccheckPairing, DuplicatedFramesAreCountedAndLeftOut) {
  ClockModel model;
  model.duplicate_probability = 0.02;
  SimulationTruth truth;
  const SyncReport report = analyse(simulate(model, 25, &truth));
  ASSERT_GT(truth.duplicated_frames, 10u);
  EXPECT_EQ(report.duplicated.frames_on_one_edge, truth.duplicated_frames);
  EXPECT_EQ(report.duplicated.repeated_frame_numbers, truth.duplicated_frames);
  EXPECT_EQ(report.dropped.dropped, truth.dropped_frames);
  // One sample per strobe in the streams, duplicates left out.
  EXPECT_EQ(report.stream(kFrameMinusEdge)->count, truth.strobes - truth.dropped_frames);
  EXPECT_EQ(report.stream(kFrameMinusKernel)->count, truth.strobes - truth.dropped_frames);
}

TEST(SynccheckPairing, FallingEdgesWhenAsked) {
  ClockModel model;
  SyncCheckOptions options;
  options.edge_polarity = EdgePolarity::kFalling;
  SimulationTruth truth;
  const SyncReport report = analyse(simulate(model, 26, &truth), options);
  EXPECT_EQ(report.edges.polarity, EdgePolarity::kFalling);
  EXPECT_EQ(report.edges.used, truth.strobes);
  EXPECT_NEAR(report.stream(kFrameMinusEdge)->offset_at_first_ns,
              model.expectedOffsetNs() - static_cast<double>(model.strobe_width_ns), kOffsetToleranceNs);
}

// A tenth of the frames stamped by the kernel (their event was late): they enter frame_minus_edge at the
// kernel's offset, 0.8 ms away; the robust line is not pulled, only the jitter shows them.
TEST(SynccheckPairing, KernelStampedFramesAreCountedAndDoNotMoveTheLine) {
  ClockModel model;
  model.event_probability = 0.9;
  SimulationTruth truth;
  const SyncReport report = analyse(simulate(model, 27, &truth));
  EXPECT_EQ(report.frames.stamped_by_kernel, truth.kernel_stamped_frames);
  EXPECT_EQ(report.frames.stamped_by_device_event, report.frames.count - truth.kernel_stamped_frames);
  EXPECT_EQ(report.frames.with_device_event, report.frames.stamped_by_device_event);
  const StreamStats* stream = report.stream(kFrameMinusEdge);
  EXPECT_NEAR(stream->offset_at_first_ns, model.expectedOffsetNs(), 30'000.0);
  EXPECT_EQ(report.stream(kDeviceEventMinusEdge)->count, report.frames.stamped_by_device_event);
  EXPECT_GT(stream->jitter_p99_ns, 600'000.0);  // the kernel-stamped frames sit ~0.8 ms off the line
}

// Edges the driver lost: their frames find no edge (unpaired, not mis-paired) and are not drops.
TEST(SynccheckPairing, LostEdgesLeaveFramesUnpairedNotMisPaired) {
  ClockModel model;
  model.drop_probability = 0.0;
  SyncInput input = simulate(model, 28);
  const std::size_t before = input.edges.size();
  // Remove the rising edges of strobes 100..104 (the sequence keeps the gap, as the driver's would).
  std::erase_if(input.edges, [](const SyncEdgeTime& e) { return e.rising && e.sequence >= 200 && e.sequence < 210; });
  ASSERT_EQ(input.edges.size(), before - 5);
  const SyncReport report = analyse(input);
  EXPECT_EQ(report.frames.without_edge, 5u);
  EXPECT_EQ(report.dropped.edges_without_frame, 0u);
  EXPECT_EQ(report.dropped.dropped, 0u);
  EXPECT_EQ(report.edges.lost_by_driver, 5u);
  EXPECT_NEAR(report.stream(kFrameMinusEdge)->offset_at_first_ns, model.expectedOffsetNs(), kOffsetToleranceNs);
}

TEST(SynccheckImu, AGapIsCountedWithItsLength) {
  ClockModel model;
  SyncInput input = simulate(model, 29);
  // Remove 100 ms of samples 10 s in: one interval of ~105 ms.
  const std::int64_t gap_start_ns = model.start_ns + 10 * kNsPerSecond;
  const std::int64_t gap_end_ns = gap_start_ns + 100 * kNsPerMillisecond;
  std::erase_if(input.imu_t_ns, [&](std::int64_t t) { return t >= gap_start_ns && t < gap_end_ns; });
  const SyncReport report = analyse(input);
  EXPECT_EQ(report.imu.gaps, 1u);
  EXPECT_NEAR(report.imu.largest_gap_ns, 105'000'000.0, 200'000.0);
  EXPECT_NEAR(report.imu.rate_hz, 200.0, 0.1);
  EXPECT_EQ(report.imu.out_of_order, 0u);
  const auto failed = report.failedChecks();
  EXPECT_EQ(failed, std::vector<std::string>{"imu_gap"});
}

}  // namespace
}  // namespace vifusion::synccheck
