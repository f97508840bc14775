#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "vifusion/clock/counter_unwrapper.hpp"
#include "vifusion/clock/tick_clock.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion::clock {
namespace {

constexpr std::uint64_t k12BitPeriod = 4096;
constexpr std::uint64_t k32BitPeriod = std::uint64_t{1} << 32;

TEST(CounterUnwrapper, TwelveBitWrapIsProgress) {
  CounterUnwrapper unwrapper(kZr300SampleCounterBits);
  EXPECT_EQ(unwrapper.period(), 4096);
  CounterUpdate u = unwrapper.update(4090);
  EXPECT_EQ(u.step, CounterStep::kFirst);
  EXPECT_EQ(u.count, 4090);  // starts at the raw value
  // 4090 … 4095, 0 … 9: sixteen steps of one, the wrap between 4095 and 0 included.
  for (std::uint64_t i = 1; i <= 16; ++i) {
    u = unwrapper.update((4090 + i) % k12BitPeriod);
    EXPECT_EQ(u.step, CounterStep::kProgress);
    EXPECT_EQ(u.count, static_cast<std::int64_t>(4090 + i));
    EXPECT_EQ(u.skipped, 0);
  }
  EXPECT_EQ(unwrapper.stats().wraps, 1u);
  // Twenty steps of 1000 from raw 10: 20000 counts, 4 more wraps (20010 / 4096 = 4.9), no gap lost.
  for (std::uint64_t k = 1; k <= 20; ++k) u = unwrapper.update((10 + 1000 * k) % k12BitPeriod);
  EXPECT_EQ(u.count, 4106 + 20000);
  EXPECT_EQ(unwrapper.stats().wraps, 5u);
  EXPECT_EQ(unwrapper.stats().skipped, 20u * 999u);
}

TEST(CounterUnwrapper, GapsCountSkippedValuesAcrossTheWrap) {
  CounterUnwrapper unwrapper(kZr300SampleCounterBits);
  unwrapper.update(4094);
  const CounterUpdate u = unwrapper.update(3);  // 4095, 0, 1, 2 skipped
  EXPECT_EQ(u.step, CounterStep::kProgress);
  EXPECT_EQ(u.skipped, 4);
  EXPECT_EQ(u.count, 4099);
  // The largest step that is still progress: half a period minus one (2047), skipping 2046.
  const CounterUpdate big = unwrapper.update(3 + 2047);
  EXPECT_EQ(big.step, CounterStep::kProgress);
  EXPECT_EQ(big.skipped, 2046);
  EXPECT_EQ(unwrapper.stats().gaps, 2u);
  EXPECT_EQ(unwrapper.stats().skipped, 2050u);
  EXPECT_EQ(counterUpdateMessage("frame_number", 3, u, 12), "frame_number = 3 skips 4 counts");
}

TEST(CounterUnwrapper, BackwardStepIsReportedNotWrapped) {
  CounterUnwrapper unwrapper(kZr300SampleCounterBits);
  unwrapper.update(100);
  unwrapper.update(101);
  // 101 → 96: "new < last" would be a wrap (+4091) in librealsense v1; here it is 5 back.
  CounterUpdate u = unwrapper.update(96);
  EXPECT_EQ(u.step, CounterStep::kBackward);
  EXPECT_EQ(u.backward_by, 5);
  EXPECT_EQ(u.count, 101);
  EXPECT_FALSE(u.applied());
  EXPECT_EQ(counterUpdateMessage("sample_counter", 96, u, 12),
            "sample_counter = 96 goes back by 5 counts (12-bit counter)");
  // Exactly half a period forward is ambiguous and treated as backward.
  u = unwrapper.update(101 + 2048);
  EXPECT_EQ(u.step, CounterStep::kBackward);
  EXPECT_EQ(u.backward_by, 2048);
  EXPECT_EQ(unwrapper.consecutiveBackward(), 2u);
  // The next good value continues from 101, as if the bad ones never came.
  u = unwrapper.update(102);
  EXPECT_EQ(u.step, CounterStep::kProgress);
  EXPECT_EQ(u.count, 102);
  EXPECT_EQ(u.skipped, 0);
  EXPECT_EQ(unwrapper.consecutiveBackward(), 0u);
  EXPECT_EQ(unwrapper.stats().backward_steps, 2u);
  EXPECT_EQ(unwrapper.stats().wraps, 0u);
}

TEST(CounterUnwrapper, RepeatAndOutOfRange) {
  CounterUnwrapper unwrapper(kZr300SampleCounterBits);
  unwrapper.update(7);
  CounterUpdate u = unwrapper.update(7);
  EXPECT_EQ(u.step, CounterStep::kRepeat);
  EXPECT_EQ(u.count, 7);
  u = unwrapper.update(4096);  // bit 12 set: not a 12-bit value
  EXPECT_EQ(u.step, CounterStep::kOutOfRange);
  EXPECT_EQ(u.count, 7);
  EXPECT_EQ(counterUpdateMessage("sample_counter", 4096, u, 12),
            "sample_counter = 4096 is out of range for a 12-bit counter");
  EXPECT_EQ(unwrapper.update(8).count, 8);
  EXPECT_EQ(unwrapper.stats().repeats, 1u);
  EXPECT_EQ(unwrapper.stats().out_of_range, 1u);
  EXPECT_EQ(unwrapper.stats().values, 4u);
}

TEST(CounterUnwrapper, DeviceRestartShowsAsBackwardRunThenResetResyncs) {
  CounterUnwrapper unwrapper(kZr300TickCounterBits);
  unwrapper.update(2'000'000'000);
  // The device restarts its tick counter near 0: 2e9 → 1e3 is 2e9 back (more than half of 2^32 forward).
  for (std::uint64_t raw = 1000; raw < 1000 + 5 * 32'000; raw += 32'000) {
    EXPECT_EQ(unwrapper.update(raw).step, CounterStep::kBackward);
  }
  EXPECT_EQ(unwrapper.consecutiveBackward(), 5u);
  unwrapper.reset();
  const CounterUpdate u = unwrapper.update(200'000);
  EXPECT_EQ(u.step, CounterStep::kFirst);
  EXPECT_EQ(u.count, 200'000);
  EXPECT_EQ(unwrapper.stats().backward_steps, 5u);  // statistics survive reset()
}

TEST(CounterUnwrapper, ThirtyTwoBitTicksAcrossTheWrapGiveMonotoneTime) {
  // 450 transfers/s of 32 MHz ticks starting 1 s before the wrap, for 3 s: the unwrapped time never jumps.
  CounterUnwrapper unwrapper(kZr300TickCounterBits);
  const std::int64_t step_ticks = kZr300MotionTicksPerSecond / 450;  // 71111 ticks = 2.222 ms
  std::int64_t true_ticks = static_cast<std::int64_t>(k32BitPeriod) - kZr300MotionTicksPerSecond;
  std::int64_t previous_ns = -1;
  for (int i = 0; i < 3 * 450; ++i, true_ticks += step_ticks) {
    const CounterUpdate u = unwrapper.update(static_cast<std::uint64_t>(true_ticks) % k32BitPeriod);
    ASSERT_TRUE(u.applied());
    EXPECT_EQ(u.count, true_ticks);
    const std::int64_t t_ns = zr300TicksToNs(u.count);
    if (previous_ns >= 0) {
      EXPECT_NEAR(t_ns - previous_ns, 2'222'219, 1);  // 71111 × 31.25 = 2222218.75 ns, rounding ±1
    }
    previous_ns = t_ns;
  }
  EXPECT_EQ(unwrapper.stats().wraps, 1u);
}

TEST(CounterUnwrapper, NearestCountPutsOtherSourcesOnTheSameTimeBase) {
  // The transfer's newest tick has just wrapped; a gyro sample in the same transfer is 100 ticks older,
  // from before the wrap, and a frame event 50 ticks newer.
  CounterUnwrapper ticks(kZr300TickCounterBits);
  ticks.update(k32BitPeriod - 1000);
  ticks.update(20);  // across the wrap: count 2^32 + 20
  const std::int64_t reference = static_cast<std::int64_t>(k32BitPeriod) + 20;
  EXPECT_EQ(ticks.count(), reference);
  EXPECT_EQ(ticks.nearestCount(k32BitPeriod - 80), reference - 100);
  EXPECT_EQ(ticks.nearestCount(70), reference + 50);
  EXPECT_EQ(ticks.nearestCount(20), reference);
  // Half a period away is taken as behind (the same rule as update()).
  EXPECT_EQ(ticks.nearestCount(20 + k32BitPeriod / 2), reference - static_cast<std::int64_t>(k32BitPeriod / 2));
  // Nothing changed, and nonsense gives the current count.
  EXPECT_EQ(ticks.count(), reference);
  EXPECT_EQ(ticks.nearestCount(k32BitPeriod), reference);
  EXPECT_EQ(ticks.stats().values, 2u);
  const CounterUnwrapper fresh(kZr300TickCounterBits);
  EXPECT_EQ(fresh.nearestCount(5), 0);
}

TEST(CounterUnwrapper, RejectsUnsupportedWidths) {
  test::expectError([] { CounterUnwrapper unwrapper(1); }, "bits = 1 must be in [2, 62]");
  test::expectError([] { CounterUnwrapper unwrapper(63); }, "bits = 63 must be in [2, 62]");
  CounterUnwrapper widest(CounterUnwrapper::kMaxBits);
  widest.update((std::uint64_t{1} << 62) - 1);
  const CounterUpdate u = widest.update(5);
  EXPECT_EQ(u.step, CounterStep::kProgress);
  EXPECT_EQ(u.count, (std::int64_t{1} << 62) + 5);
}

}  // namespace
}  // namespace vifusion::clock
