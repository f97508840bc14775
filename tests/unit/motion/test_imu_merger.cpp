// Accelerometer/gyro merge: exact on linear signals, never extrapolates, drops and names bad input.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "vifusion/motion/imu_merger.hpp"
#include "vifusion/test/counting_allocations.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion::motion {
namespace {

constexpr std::int64_t kMs = kNsPerMillisecond;
constexpr std::int64_t kAccelPeriodNs = 4 * kMs;  // 250 Hz
constexpr std::int64_t kGyroPeriodNs = 5 * kMs;   // 200 Hz

/// A specific force varying linearly in time, different on each axis [m/s², t in s].
Eigen::Vector3d linearAccel(std::int64_t t_ns) {
  const double t_s = nsToSeconds(t_ns);
  return Eigen::Vector3d(0.3 + 2.0 * t_s, -9.81 - 0.7 * t_s, 1.5 * t_s - 4.0);
}

Eigen::Vector3d gyroAt(std::int64_t t_ns) { return Eigen::Vector3d(0.01, -0.02, 0.03) * nsToSeconds(t_ns); }

std::string text(const MergeProblem& problem) { return std::string(describe(problem).view()); }

/// Feeds both streams in arrival order (by time, accelerometer first on ties) and pops after every push.
std::vector<ImuSample> mergeStreams(ImuMerger& merger, std::int64_t t_begin_ns, std::int64_t t_end_ns,
                                    std::int64_t gyro_offset_ns) {
  std::vector<ImuSample> merged;
  std::int64_t t_accel = t_begin_ns;
  std::int64_t t_gyro = t_begin_ns + gyro_offset_ns;
  ImuSample sample;
  while (t_accel <= t_end_ns || t_gyro <= t_end_ns) {
    if (t_accel <= t_gyro) {
      merger.pushAccel(t_accel, linearAccel(t_accel));
      t_accel += kAccelPeriodNs;
    } else {
      merger.pushGyro(t_gyro, gyroAt(t_gyro));
      t_gyro += kGyroPeriodNs;
    }
    while (merger.popMerged(sample)) merged.push_back(sample);
  }
  return merged;
}

TEST(ImuMerger, InterpolatesLinearSignalsExactlyAtEveryGyroTime) {
  ImuMerger merger;
  const std::int64_t t_begin_ns = 1'000'000'000;  // gyro 1.3 ms after the accelerometer, then drifting in phase
  const std::vector<ImuSample> merged = mergeStreams(merger, t_begin_ns, t_begin_ns + 10 * kNsPerSecond, 1'300'000);
  ASSERT_EQ(merged.size(), 2000u);  // every gyro sample of 10 s at 200 Hz
  double max_error_mps2 = 0.0;
  for (std::size_t i = 0; i < merged.size(); ++i) {
    const std::int64_t t_ns = t_begin_ns + 1'300'000 + static_cast<std::int64_t>(i) * kGyroPeriodNs;
    ASSERT_EQ(merged[i].t_ns, t_ns);
    EXPECT_EQ(merged[i].gyro_rad_s, gyroAt(t_ns)) << "gyro passes through unaltered";
    max_error_mps2 = std::max(max_error_mps2, (merged[i].accel_mps2 - linearAccel(t_ns)).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(max_error_mps2, 1e-12);
  EXPECT_EQ(merger.stats().merged, 2000u);
  EXPECT_EQ(merger.stats().totalDrops(), 0u) << text(merger.lastProblem());
}

TEST(ImuMerger, SkewedArrivalStillMergesEverySample) {
  // All accelerometer samples of a 40 ms burst arrive before the gyro samples of the same span.
  ImuMerger merger;
  ImuSample sample;
  std::size_t merged = 0;
  for (std::int64_t block = 0; block < 50; ++block) {
    const std::int64_t t0 = block * 40 * kMs;
    for (std::int64_t t = t0; t < t0 + 40 * kMs; t += kAccelPeriodNs) merger.pushAccel(t, linearAccel(t));
    for (std::int64_t t = t0 + kMs; t < t0 + 40 * kMs; t += kGyroPeriodNs) merger.pushGyro(t, gyroAt(t));
    while (merger.popMerged(sample)) {
      EXPECT_NEAR((sample.accel_mps2 - linearAccel(sample.t_ns)).norm(), 0.0, 1e-12);
      ++merged;
    }
  }
  EXPECT_EQ(merged, 50u * 8u);
  EXPECT_EQ(merger.stats().totalDrops(), 0u);
}

TEST(ImuMerger, NeverExtrapolates) {
  ImuMerger merger;
  ImuSample sample;
  merger.pushAccel(0, Eigen::Vector3d(0, 0, 0));
  merger.pushAccel(4 * kMs, Eigen::Vector3d(4, 8, -4));
  merger.pushGyro(5 * kMs, Eigen::Vector3d(1, 2, 3));
  EXPECT_FALSE(merger.popMerged(sample)) << "no accelerometer sample at or after 5 ms yet";
  merger.pushAccel(8 * kMs, Eigen::Vector3d(8, 16, -8));
  ASSERT_TRUE(merger.popMerged(sample));
  EXPECT_EQ(sample.t_ns, 5 * kMs);
  EXPECT_NEAR((sample.accel_mps2 - Eigen::Vector3d(5, 10, -5)).norm(), 0.0, 1e-12);
  // A gyro sample at an accelerometer sample's time takes that sample as it is, without waiting.
  merger.pushGyro(8 * kMs, Eigen::Vector3d(0, 0, 1));
  ASSERT_TRUE(merger.popMerged(sample));
  EXPECT_EQ(sample.accel_mps2, Eigen::Vector3d(8, 16, -8));
  EXPECT_FALSE(merger.popMerged(sample));
}

TEST(ImuMerger, GyroBeforeTheFirstAccelerometerSampleIsDropped) {
  ImuMerger merger;
  ImuSample sample;
  merger.pushGyro(1 * kMs, Eigen::Vector3d::Zero());
  merger.pushGyro(6 * kMs, Eigen::Vector3d::Zero());
  EXPECT_FALSE(merger.popMerged(sample)) << "waits while no accelerometer sample exists";
  merger.pushAccel(2 * kMs, Eigen::Vector3d::Zero());
  merger.pushAccel(6 * kMs, Eigen::Vector3d::Ones());
  ASSERT_TRUE(merger.popMerged(sample));
  EXPECT_EQ(sample.t_ns, 6 * kMs);
  EXPECT_EQ(merger.stats().dropCount(ImuStream::kGyroscope, MergeDropReason::kGyroBeforeAccel), 1u);
  EXPECT_EQ(text(merger.lastProblem()),
            "gyroscope sample t_ns 1000000 precedes the oldest buffered accelerometer sample at 2000000: no bracket "
            "without extrapolating, dropped");
}

TEST(ImuMerger, DuplicateOutOfOrderAndNonFiniteSamplesAreDroppedByName) {
  ImuMerger merger;
  EXPECT_TRUE(merger.pushAccel(10 * kMs, Eigen::Vector3d::Zero()));
  EXPECT_FALSE(merger.pushAccel(10 * kMs, Eigen::Vector3d::Zero()));
  EXPECT_EQ(text(merger.lastProblem()),
            "accelerometer sample t_ns 10000000 is not after the previous accelerometer sample at 10000000 "
            "(duplicate time): dropped");
  EXPECT_FALSE(merger.pushAccel(7 * kMs, Eigen::Vector3d::Zero()));
  EXPECT_EQ(text(merger.lastProblem()),
            "accelerometer sample t_ns 7000000 goes back by 3000000 ns from the previous accelerometer sample at "
            "10000000 (out of order): dropped");
  EXPECT_TRUE(merger.pushGyro(11 * kMs, Eigen::Vector3d::Zero()));
  EXPECT_FALSE(merger.pushGyro(11 * kMs, Eigen::Vector3d::Zero()));
  EXPECT_FALSE(merger.pushGyro(9 * kMs, Eigen::Vector3d::Zero()));
  EXPECT_FALSE(merger.pushGyro(12 * kMs, Eigen::Vector3d(0, std::numeric_limits<double>::quiet_NaN(), 0)));
  EXPECT_EQ(text(merger.lastProblem()), "gyroscope sample t_ns 12000000 has a NaN or infinite axis value: dropped");
  EXPECT_FALSE(merger.pushAccel(13 * kMs, Eigen::Vector3d(std::numeric_limits<double>::infinity(), 0, 0)));
  EXPECT_TRUE(merger.pushGyro(12 * kMs, Eigen::Vector3d::Zero())) << "a dropped NaN sample does not advance time";

  const ImuMergerStats& stats = merger.stats();
  EXPECT_EQ(stats.dropCount(ImuStream::kAccelerometer, MergeDropReason::kDuplicateTime), 1u);
  EXPECT_EQ(stats.dropCount(ImuStream::kAccelerometer, MergeDropReason::kOutOfOrderTime), 1u);
  EXPECT_EQ(stats.dropCount(ImuStream::kGyroscope, MergeDropReason::kDuplicateTime), 1u);
  EXPECT_EQ(stats.dropCount(ImuStream::kGyroscope, MergeDropReason::kOutOfOrderTime), 1u);
  EXPECT_EQ(stats.dropCount(ImuStream::kGyroscope, MergeDropReason::kNonFiniteValue), 1u);
  EXPECT_EQ(stats.dropCount(ImuStream::kAccelerometer, MergeDropReason::kNonFiniteValue), 1u);
  EXPECT_EQ(stats.totalDrops(), 6u);
  EXPECT_EQ(stats.accel_in, 1u);
  EXPECT_EQ(stats.gyro_in, 2u);
}

TEST(ImuMerger, GyroInsideAnAccelerometerGapIsDropped) {
  ImuMerger merger;  // max_accel_gap_ns 20 ms
  ImuSample sample;
  merger.pushAccel(0, Eigen::Vector3d::Zero());
  merger.pushAccel(40 * kMs, Eigen::Vector3d::Ones());
  merger.pushGyro(10 * kMs, Eigen::Vector3d::Zero());
  merger.pushAccel(44 * kMs, Eigen::Vector3d::Ones());
  merger.pushGyro(42 * kMs, Eigen::Vector3d::Zero());
  ASSERT_TRUE(merger.popMerged(sample));
  EXPECT_EQ(sample.t_ns, 42 * kMs) << "after the gap merging resumes";
  EXPECT_EQ(merger.stats().dropCount(ImuStream::kGyroscope, MergeDropReason::kAccelGap), 1u);
  EXPECT_EQ(text(merger.lastProblem()),
            "gyroscope sample t_ns 10000000 falls in an accelerometer gap of 40000000 ns, above max_accel_gap_ns "
            "20000000: dropped");
}

TEST(ImuMerger, FullBuffersDropTheirOldestSample) {
  ImuMerger merger({.accel_capacity = 4, .gyro_capacity = 3});
  for (int i = 1; i <= 5; ++i) merger.pushGyro(i * kMs, Eigen::Vector3d::Zero());  // accelerometer stalled
  EXPECT_EQ(merger.stats().dropCount(ImuStream::kGyroscope, MergeDropReason::kBufferFull), 2u);
  EXPECT_EQ(text(merger.lastProblem()),
            "gyroscope buffer full: its oldest sample t_ns 2000000 dropped (merged samples not popped, or the other "
            "stream stalled)");
  // Then both streams flow (accelerometer 2, 6, … 998 ms; gyro 6, 11, … 996 ms): the 3 waiting gyro samples
  // merge first, and accelerometer samples that no gyro sample can need any more are pruned silently, so
  // 4 slots are enough and nothing else is dropped.
  const std::vector<ImuSample> merged = mergeStreams(merger, 2 * kMs, 1 * kNsPerSecond, 4 * kMs);
  ASSERT_EQ(merged.size(), 3u + 199u);
  EXPECT_EQ(merged.front().t_ns, 3 * kMs);
  EXPECT_EQ(merged.back().t_ns, 996 * kMs);
  EXPECT_EQ(merger.stats().totalDrops(), 2u) << text(merger.lastProblem());
  // The gyroscope stalls: a future gyro sample might need any newer accelerometer sample, so the full buffer
  // (994 and 998 ms kept, then 1001 … 1006 ms) drops its oldest, 4 times.
  for (int i = 1; i <= 6; ++i) merger.pushAccel(1 * kNsPerSecond + i * kMs, Eigen::Vector3d::Zero());
  EXPECT_EQ(merger.stats().dropCount(ImuStream::kAccelerometer, MergeDropReason::kBufferFull), 4u);
}

TEST(ImuMerger, OptionsAreValidatedByName) {
  vifusion::test::expectError([] { ImuMerger({.accel_capacity = 1}); }, "'accel_capacity' = 1 must be >= 2");
  vifusion::test::expectError([] { ImuMerger({.gyro_capacity = 0}); }, "'gyro_capacity' = 0 must be >= 1");
  vifusion::test::expectError([] { ImuMerger({.max_accel_gap_ns = 0}); }, "'max_accel_gap_ns' = 0 must be > 0");
}

TEST(ImuMerger, ResetForgetsTimesAndSamples) {
  ImuMerger merger;
  merger.pushAccel(100 * kMs, Eigen::Vector3d::Zero());
  merger.pushGyro(100 * kMs, Eigen::Vector3d::Zero());
  merger.reset();
  EXPECT_TRUE(merger.pushAccel(1 * kMs, Eigen::Vector3d::Zero())) << "earlier times are accepted after reset";
  EXPECT_EQ(merger.stats().accel_in, 1u);
}

TEST(ImuMerger, SteadyStateAllocatesNothing) {
  ImuMerger merger;
  ImuSample sample;
  std::size_t merged = 0;
  const std::uint64_t before = vifusion::test::heapAllocationCount();
  for (std::int64_t t = 0; t < 2 * kNsPerSecond; t += kMs) {
    if (t % kAccelPeriodNs == 0) merger.pushAccel(t, linearAccel(t));
    if (t % kGyroPeriodNs == 0) merger.pushGyro(t, gyroAt(t));
    merger.pushGyro(t, gyroAt(t));  // mostly duplicates: the drop path too
    while (merger.popMerged(sample)) ++merged;
    describe(merger.lastProblem());
  }
  EXPECT_EQ(vifusion::test::heapAllocationCount() - before, 0u);
  EXPECT_GT(merged, 300u);
}

}  // namespace
}  // namespace vifusion::motion
