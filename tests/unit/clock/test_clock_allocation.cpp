#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "simulated_link.hpp"
#include "vifusion/clock/clock_mapper.hpp"
#include "vifusion/clock/counter_unwrapper.hpp"
#include "vifusion/clock/tick_clock.hpp"
#include "vifusion/test/counting_allocations.hpp"

namespace vifusion::clock {
namespace {

TEST(ClockAllocation, PerSamplePathAllocatesNothing) {
  // Start-up: the mapper (window ring, hull, scratch), the unwrappers, the simulated link.
  ClockMapperOptions options;
  options.window_samples = 2048;  // small, so the window wraps and expires by count as well as by time
  ClockMapper mapper(options);
  CounterUnwrapper ticks(kZr300TickCounterBits);
  CounterUnwrapper sample_numbers(kZr300SampleCounterBits);
  test::LinkModel model;
  model.host_pause_after_ns = 20 * kNsPerSecond;  // a clock step and restart on the way
  model.host_pause_ns = kNsPerSecond;
  test::SimulatedLink link(model, 21);

  const std::uint64_t before = vifusion::test::heapAllocationCount();
  std::int64_t checksum = 0;
  for (int i = 0; i < 40 * 450; ++i) {
    const test::LinkSample s = link.next();
    const std::int64_t raw_ticks = nsToTicks(s.device_ns, kZr300MotionTicksPerSecond) % (std::int64_t{1} << 32);
    const CounterUpdate tick = ticks.update(static_cast<std::uint64_t>(raw_ticks));
    checksum += sample_numbers.update(static_cast<std::uint64_t>(i % 4096)).skipped;
    checksum += mapper.addSample(zr300TicksToNs(tick.count), s.receive_ns).accepted() ? 1 : 0;
    // The rejection paths too, as long as nobody asks for the message.
    checksum += mapper.addSample(zr300TicksToNs(tick.count), s.receive_ns).accepted() ? 1 : 0;
    checksum += mapper.addSample(-1, s.receive_ns).accepted() ? 1 : 0;
    checksum += ticks.update(raw_ticks == 0 ? 1 : static_cast<std::uint64_t>(raw_ticks - 1)).count;
    checksum += ticks.nearestCount(static_cast<std::uint64_t>(raw_ticks));
    checksum += mapper.toHostNs(zr300TicksToNs(tick.count)).value_or(0) + mapper.offsetNs();
  }
  EXPECT_EQ(vifusion::test::heapAllocationCount(), before);
  EXPECT_NE(checksum, 0);
  EXPECT_EQ(mapper.stats().restarts, 1u);
  EXPECT_TRUE(mapper.valid());
  EXPECT_EQ(mapper.windowSize(), 2048u);
  // The counter does see allocations.
  const std::vector<int> probe(3);
  EXPECT_GT(vifusion::test::heapAllocationCount(), before);
}

}  // namespace
}  // namespace vifusion::clock
