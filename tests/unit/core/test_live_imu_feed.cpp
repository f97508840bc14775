// LiveImuFeed: the window it hands out (covers the frame, keeps the retained history, sorted), the bounded
// wait for a late sample, the counted drops, and no allocation per frame.

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "vifusion/core/error.hpp"
#include "vifusion/core/live_imu_feed.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/test/counting_allocations.hpp"

namespace vifusion {
namespace {

constexpr std::int64_t kImuPeriodNs = 5'000'000;  // 200 Hz
constexpr std::int64_t kFramePeriodNs = 33'333'333;

ImuSample sampleAt(std::int64_t t_ns) {
  ImuSample sample;
  sample.t_ns = t_ns;
  sample.gyro_rad_s.x() = static_cast<double>(t_ns) * 1e-9;
  return sample;
}

/// Pushes samples every kImuPeriodNs in [first, last].
void pushRange(SpscRing<ImuSample>& ring, std::int64_t first_ns, std::int64_t last_ns) {
  for (std::int64_t t = first_ns; t <= last_ns; t += kImuPeriodNs) ASSERT_TRUE(ring.tryPush(sampleAt(t)));
}

bool sorted(std::span<const ImuSample> window) {
  for (std::size_t i = 1; i < window.size(); ++i) {
    if (window[i].t_ns <= window[i - 1].t_ns) return false;
  }
  return true;
}

TEST(LiveImuFeed, WindowCoversTheFrameAndKeepsTheRetainedHistory) {
  SpscRing<ImuSample> ring(1024);
  LiveImuFeedOptions options;
  options.retain_ns = 200'000'000;
  options.time_shift_cam_imu_ns = 1'000'000;  // t_imu = t_cam + 1 ms
  LiveImuFeed feed(ring, options);
  pushRange(ring, 0, 2 * kNsPerSecond);

  const std::int64_t t_cam = kNsPerSecond;
  std::span<const ImuSample> window = feed.samplesThrough(t_cam);
  ASSERT_FALSE(window.empty());
  EXPECT_TRUE(sorted(window));
  // First frame: history back to t_imu − retain (the last sample at or before it kept), all later samples.
  const std::int64_t t_imu = t_cam + options.time_shift_cam_imu_ns;
  EXPECT_EQ(window.front().t_ns, (t_imu - options.retain_ns) / kImuPeriodNs * kImuPeriodNs);
  EXPECT_EQ(window.back().t_ns, 2 * kNsPerSecond);

  // Next frame: history is kept from the previous frame's IMU time − retain.
  window = feed.samplesThrough(t_cam + kFramePeriodNs);
  EXPECT_EQ(window.front().t_ns, (t_imu - options.retain_ns) / kImuPeriodNs * kImuPeriodNs);
  window = feed.samplesThrough(t_cam + 2 * kFramePeriodNs);
  const std::int64_t previous_imu = t_cam + kFramePeriodNs + options.time_shift_cam_imu_ns;
  EXPECT_EQ(window.front().t_ns, (previous_imu - options.retain_ns) / kImuPeriodNs * kImuPeriodNs);
  EXPECT_EQ(feed.stats().late_frames, 0u);
  EXPECT_EQ(feed.stats().samples, 401u);
}

TEST(LiveImuFeed, WaitsForALateSampleThenHandsItOver) {
  SpscRing<ImuSample> ring(1024);
  LiveImuFeedOptions options;
  options.max_wait_ns = 5 * kNsPerSecond;  // generous: the producer below is 20 ms late
  LiveImuFeed feed(ring, options);
  pushRange(ring, 0, 100'000'000);
  std::thread producer([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    pushRange(ring, 105'000'000, 150'000'000);
  });
  const auto start = std::chrono::steady_clock::now();
  const std::span<const ImuSample> window = feed.samplesThrough(120'000'000);
  const double waited_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  producer.join();
  ASSERT_FALSE(window.empty());
  EXPECT_GE(window.back().t_ns, 120'000'000);
  EXPECT_EQ(feed.stats().late_frames, 0u);
  EXPECT_LT(waited_s, 2.0);  // it returned when the sample came, not at max_wait
}

TEST(LiveImuFeed, ASampleThatNeverComesEndsTheWaitAndIsCounted) {
  SpscRing<ImuSample> ring(1024);
  LiveImuFeedOptions options;
  options.max_wait_ns = 30'000'000;
  LiveImuFeed feed(ring, options);
  pushRange(ring, 0, 100'000'000);
  const auto start = std::chrono::steady_clock::now();
  const std::span<const ImuSample> window = feed.samplesThrough(200'000'000);
  const double waited_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_GE(waited_s, 0.030);
  EXPECT_EQ(feed.stats().late_frames, 1u);
  ASSERT_FALSE(window.empty());
  EXPECT_LT(window.back().t_ns, 200'000'000);  // never extrapolated: the pipeline's check refuses the frame
}

TEST(LiveImuFeed, SamplesGoingBackInTimeAreDroppedAndCounted) {
  SpscRing<ImuSample> ring(1024);
  LiveImuFeed feed(ring, LiveImuFeedOptions{});
  pushRange(ring, 0, 50'000'000);
  ASSERT_TRUE(ring.tryPush(sampleAt(20'000'000)));  // back by 30 ms
  ASSERT_TRUE(ring.tryPush(sampleAt(50'000'000)));  // a repeat
  pushRange(ring, 55'000'000, 80'000'000);
  const std::span<const ImuSample> window = feed.samplesThrough(60'000'000);
  EXPECT_TRUE(sorted(window));
  EXPECT_EQ(feed.stats().out_of_order, 2u);
  EXPECT_EQ(window.back().t_ns, 80'000'000);
}

TEST(LiveImuFeed, AFullWindowDropsItsOldestSamplesAndCountsThem) {
  SpscRing<ImuSample> ring(4096);
  LiveImuFeedOptions options;
  options.window_capacity = 64;
  LiveImuFeed feed(ring, options);
  pushRange(ring, 0, 99 * kImuPeriodNs);  // 100 samples into a 64-sample window
  const std::span<const ImuSample> window = feed.samplesThrough(99 * kImuPeriodNs);
  EXPECT_LE(window.size(), 64u);
  EXPECT_EQ(window.back().t_ns, 99 * kImuPeriodNs);
  EXPECT_EQ(feed.stats().window_drops + window.size(), 100u);
  EXPECT_TRUE(sorted(window));
}

TEST(LiveImuFeed, SteadyStateAllocatesNothing) {
  SpscRing<ImuSample> ring(4096);
  LiveImuFeed feed(ring, LiveImuFeedOptions{});
  std::int64_t pushed_through = -kImuPeriodNs;
  auto streamTo = [&](std::int64_t t_ns) {
    for (std::int64_t t = pushed_through + kImuPeriodNs; t <= t_ns; t += kImuPeriodNs) {
      ASSERT_TRUE(ring.tryPush(sampleAt(t)));
      pushed_through = t;
    }
  };
  for (int frame = 0; frame < 60; ++frame) {  // warm-up past the retained second
    streamTo(frame * kFramePeriodNs + 10'000'000);
    feed.samplesThrough(frame * kFramePeriodNs);
  }
  const std::uint64_t before = test::heapAllocationCount();
  for (int frame = 60; frame < 600; ++frame) {
    streamTo(frame * kFramePeriodNs + 10'000'000);
    feed.samplesThrough(frame * kFramePeriodNs);
  }
  EXPECT_EQ(test::heapAllocationCount(), before);
  EXPECT_EQ(feed.stats().late_frames, 0u);
  EXPECT_EQ(feed.stats().window_drops, 0u);
}

TEST(LiveImuFeed, OptionsOutOfRangeAreNamed) {
  SpscRing<ImuSample> ring(16);
  LiveImuFeedOptions options;
  options.window_capacity = 4;
  EXPECT_THROW(
      {
        try {
          LiveImuFeed feed(ring, options);
        } catch (const Error& error) {
          EXPECT_NE(std::string(error.what()).find("window_capacity"), std::string::npos);
          throw;
        }
      },
      Error);
  options = {};
  options.max_wait_ns = -1;
  EXPECT_THROW(options.validate(), Error);
  options = {};
  options.retain_ns = 61 * kNsPerSecond;
  EXPECT_THROW(options.validate(), Error);
}

}  // namespace
}  // namespace vifusion
