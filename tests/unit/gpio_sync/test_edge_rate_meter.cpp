#include <gtest/gtest.h>

#include <cstdint>

#include "vifusion/core/time.hpp"
#include "vifusion/gpio_sync/edge_rate_meter.hpp"
#include "vifusion/test/counting_allocations.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion::gpio_sync {
namespace {

constexpr std::int64_t kStrobePeriodNs = 33'333'333;  // a 30 Hz strobe, as the camera's clock rounds it
constexpr std::int64_t kStartNs = 5 * kNsPerSecond;
constexpr double kRateToleranceHz = 1e-5;

/// Adds `count` edges `period_ns` apart from `first_ns`; returns the last edge's time.
std::int64_t addPeriodic(EdgeRateMeter& meter, std::int64_t first_ns, std::int64_t period_ns, int count) {
  std::int64_t t_ns = first_ns;
  for (int i = 0; i < count; ++i, t_ns += period_ns) EXPECT_TRUE(meter.add(t_ns));
  return t_ns - period_ns;
}

TEST(EdgeRateMeter, ReadsAThirtyHertzStrobeAsThirtyWhateverTheWindowPhase) {
  EdgeRateMeter meter(256, kNsPerSecond);
  const std::int64_t last_ns = addPeriodic(meter, kStartNs, kStrobePeriodNs, 90);
  // 1 / 33.333333 ms = 30.0000003 Hz; n / window would read 30 or 31 depending on where the window starts.
  EXPECT_NEAR(meter.rateHz(last_ns), 30.0, kRateToleranceHz);
  EXPECT_NEAR(meter.rateHz(last_ns + kStrobePeriodNs / 2), 30.0, kRateToleranceHz);
  EXPECT_NEAR(meter.rateHz(last_ns + kStrobePeriodNs - 1), 30.0, kRateToleranceHz);
}

TEST(EdgeRateMeter, ReadsZeroOneWindowAfterTheLineFallsSilent) {
  EdgeRateMeter meter(256, kNsPerSecond);
  const std::int64_t last_ns = addPeriodic(meter, kStartNs, kStrobePeriodNs, 60);
  // Half a window later the edges still inside give the true rate; a full window later none are left.
  EXPECT_NEAR(meter.rateHz(last_ns + kNsPerSecond / 2), 30.0, kRateToleranceHz);
  EXPECT_EQ(meter.rateHz(last_ns + kNsPerSecond), 0.0);
  // Only one edge left in the window: no interval, no rate.
  EXPECT_EQ(meter.rateHz(last_ns + kNsPerSecond - kStrobePeriodNs / 2), 0.0);
}

TEST(EdgeRateMeter, FollowsARateChangeWithinOneWindow) {
  EdgeRateMeter meter(256, kNsPerSecond);
  std::int64_t last_ns = addPeriodic(meter, kStartNs, kStrobePeriodNs, 60);
  constexpr std::int64_t kSixtyHzPeriodNs = 16'666'667;
  last_ns = addPeriodic(meter, last_ns + kSixtyHzPeriodNs, kSixtyHzPeriodNs, 120);
  EXPECT_NEAR(meter.rateHz(last_ns), 1e9 / kSixtyHzPeriodNs, kRateToleranceHz);
}

TEST(EdgeRateMeter, MoreEdgesThanCapacityInTheWindowStillGiveTheRate) {
  EdgeRateMeter meter(4, kNsPerSecond);  // a 1 kHz trigger: 1000 edges in the window, 4 kept
  const std::int64_t last_ns = addPeriodic(meter, kStartNs, kNsPerMillisecond, 1000);
  EXPECT_EQ(meter.stored(), 4u);
  EXPECT_NEAR(meter.rateHz(last_ns), 1000.0, kRateToleranceHz);
}

TEST(EdgeRateMeter, IgnoresAnEdgeOlderThanTheNewest) {
  EdgeRateMeter meter(16, kNsPerSecond);
  const std::int64_t last_ns = addPeriodic(meter, kStartNs, kStrobePeriodNs, 10);
  EXPECT_FALSE(meter.add(last_ns - 1));
  EXPECT_EQ(meter.stored(), 10u);
  EXPECT_NEAR(meter.rateHz(last_ns), 30.0, kRateToleranceHz);
  EXPECT_TRUE(meter.add(last_ns));  // an equal time is not older
}

TEST(EdgeRateMeter, NoEdgesOrOneEdgeReadZeroAndResetForgets) {
  EdgeRateMeter meter(16, kNsPerSecond);
  EXPECT_EQ(meter.rateHz(kStartNs), 0.0);
  meter.add(kStartNs);
  EXPECT_EQ(meter.rateHz(kStartNs), 0.0);
  const std::int64_t last_ns = addPeriodic(meter, kStartNs + kStrobePeriodNs, kStrobePeriodNs, 5);
  EXPECT_GT(meter.rateHz(last_ns), 0.0);
  meter.reset();
  EXPECT_EQ(meter.stored(), 0u);
  EXPECT_EQ(meter.rateHz(last_ns), 0.0);
  EXPECT_TRUE(meter.add(kStartNs));  // after reset, earlier times are accepted again
}

TEST(EdgeRateMeter, RejectsAMeterThatCannotMeasure) {
  test::expectError([] { EdgeRateMeter(1, kNsPerSecond); }, "EdgeRateMeter: capacity must be >= 2, got 1");
  test::expectError([] { EdgeRateMeter(8, 0); }, "EdgeRateMeter: window_ns must be > 0, got 0");
}

TEST(EdgeRateMeter, AddAndRateAllocateNothing) {
  EdgeRateMeter meter(256, kNsPerSecond);
  const std::uint64_t before = test::heapAllocationCount();
  double sum_hz = 0.0;
  std::int64_t t_ns = kStartNs;
  for (int i = 0; i < 10'000; ++i, t_ns += kStrobePeriodNs) {
    meter.add(t_ns);
    sum_hz += meter.rateHz(t_ns);
  }
  EXPECT_EQ(test::heapAllocationCount() - before, 0u);
  EXPECT_GT(sum_hz, 0.0);
}

}  // namespace
}  // namespace vifusion::gpio_sync
