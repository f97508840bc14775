#include <gtest/gtest.h>

#include <cstdint>

#include "vifusion/clock/tick_clock.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion::clock {
namespace {

constexpr std::int64_t kTickPeriod32Bit = std::int64_t{1} << 32;

TEST(TickClock, ConvertsZr300TicksExactly) {
  // 31.25 ns per tick: four ticks are exactly 125 ns, one second is exactly 32e6 ticks.
  EXPECT_EQ(zr300TicksToNs(0), 0);
  EXPECT_EQ(zr300TicksToNs(4), 125);
  EXPECT_EQ(zr300TicksToNs(kZr300MotionTicksPerSecond), kNsPerSecond);
  // Fractions round to nearest, halves up: 31.25 → 31, 62.5 → 63, 93.75 → 94.
  EXPECT_EQ(zr300TicksToNs(1), 31);
  EXPECT_EQ(zr300TicksToNs(2), 63);
  EXPECT_EQ(zr300TicksToNs(3), 94);
  // One 32-bit period: 2^32 × 31.25 ns = 134.217728 s, exactly (librealsense v1 used 2^32 − 1 ticks).
  EXPECT_EQ(zr300TicksToNs(kTickPeriod32Bit), 134'217'728'000);
}

TEST(TickClock, NoDriftOverYearsOfTicks) {
  // Ten years of ticks: a rounded 31 ns/tick would be 2.5 months off; the exact rule is 0 ns off.
  const std::int64_t ten_years_s = 10LL * 365 * 24 * 3600;
  const std::int64_t ticks = ten_years_s * kZr300MotionTicksPerSecond;
  EXPECT_EQ(zr300TicksToNs(ticks), ten_years_s * kNsPerSecond);
  EXPECT_EQ(zr300TicksToNs(ticks + 3), ten_years_s * kNsPerSecond + 94);
  // Multiples of 4 ticks are exact at any magnitude.
  for (std::int64_t k : {1LL, 977LL, 123'456'789LL, 9'000'000'000'000LL}) EXPECT_EQ(zr300TicksToNs(4 * k), 125 * k);
}

TEST(TickClock, MonotoneAndRoundTrips) {
  std::int64_t previous_ns = -1;
  for (std::int64_t ticks = kTickPeriod32Bit - 1000; ticks < kTickPeriod32Bit + 1000; ++ticks) {
    const std::int64_t t_ns = zr300TicksToNs(ticks);
    EXPECT_GT(t_ns, previous_ns);  // 31.25 ns per tick: strictly increasing
    previous_ns = t_ns;
    // The nearest tick of a converted time is the tick itself (rounding moved it by at most 0.5 ns).
    EXPECT_EQ(nsToTicks(t_ns, kZr300MotionTicksPerSecond), ticks);
  }
}

TEST(TickClock, OtherRates) {
  // A 1 kHz counter: whole milliseconds. A 3 Hz counter: 333333333.33 → 333333333 ns, 2 ticks → 666666667.
  EXPECT_EQ(ticksToNs(1500, 1000), 1'500'000'000);
  EXPECT_EQ(ticksToNs(1, 3), 333'333'333);
  EXPECT_EQ(ticksToNs(2, 3), 666'666'667);
  EXPECT_EQ(nsToTicks(500'000'000, 3), 2);  // 1.5 ticks rounds up
}

}  // namespace
}  // namespace vifusion::clock
