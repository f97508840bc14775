// SyncLine over the REAL libgpiod 1.6 (LibgpiodLineIo) against a GPIO chip emulated by umockdev at the v1
// character-device level (umockdev_gpio_chip.hpp): chip info, line info, the event request and the event
// records all pass through libgpiod as they would from the kernel. Runs under umockdev-wrapper.
#include <gtest/gtest.h>
#include <linux/gpio.h>

#include <chrono>
#include <ctime>
#include <memory>
#include <thread>
#include <vector>

#include "umockdev_gpio_chip.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/gpio_sync/libgpiod_line_io.hpp"
#include "vifusion/gpio_sync/sync_line.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion::gpio_sync {
namespace {

using test::UmockdevGpioChip;

constexpr auto kPatience = std::chrono::seconds(5);
constexpr std::int64_t kStrobePeriodNs = 33'333'333;
constexpr unsigned kStrobeLine = 3;

template <class Predicate>
bool waitFor(Predicate predicate) {
  const auto deadline = std::chrono::steady_clock::now() + kPatience;
  while (!predicate()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

SyncLineOptions strobeOptions(EdgeDetection edges = EdgeDetection::kRising) {
  SyncLineOptions options;
  options.chip = UmockdevGpioChip::kChipName;
  options.line_offset = kStrobeLine;
  options.edges = edges;
  options.wait_timeout_ms = 20;
  return options;
}

std::vector<SyncEdge> popAll(SyncLine& line) {
  std::vector<SyncEdge> out;
  SyncEdge edge;
  while (line.edgeRing().tryPop(edge)) out.push_back(edge);
  return out;
}

TEST(LibgpiodUmockdev, RequestsEdgeEventsOnTheLineAsVifusionSync) {
  UmockdevGpioChip chip;
  LibgpiodLineIo io;
  io.open(UmockdevGpioChip::kChipName, kStrobeLine, EdgeDetection::kBoth);
  EXPECT_EQ(chip.eventRequests(), 1);
  EXPECT_EQ(chip.requestedLine(), kStrobeLine);
  EXPECT_EQ(chip.requestedEventFlags(), static_cast<std::uint32_t>(GPIOEVENT_REQUEST_BOTH_EDGES));
  EXPECT_EQ(chip.requestedConsumer(), "vifusion-sync");
  io.close();
  io.open("/dev/gpiochip0", kStrobeLine, EdgeDetection::kRising);  // the same chip by path
  EXPECT_EQ(chip.requestedEventFlags(), static_cast<std::uint32_t>(GPIOEVENT_REQUEST_RISING_EDGE));
}

TEST(LibgpiodUmockdev, AnOutOfRangeLineNamesTheChipsLineCount) {
  UmockdevGpioChip chip;
  LibgpiodLineIo io;
  vifusion::test::expectError([&] { io.open(UmockdevGpioChip::kChipName, 8, EdgeDetection::kRising); },
                              "gpiochip0 line 8: out of range, the chip has 8 lines (offsets 0 to 7)");
  EXPECT_EQ(chip.eventRequests(), 0);
}

TEST(LibgpiodUmockdev, ABusyLineNamesItsHolder) {
  UmockdevGpioChip chip;
  LibgpiodLineIo io;
  vifusion::test::expectError(
      [&] { io.open(UmockdevGpioChip::kChipName, UmockdevGpioChip::kBusyLine, EdgeDetection::kRising); },
      "gpiochip0 line 6: cannot request rising edge events: the line is busy, held by \"gpio-keys\" "
      "(Device or resource busy)");
}

TEST(LibgpiodUmockdev, StreamsKernelStampedEdgesInOrderWithTheirRate) {
  UmockdevGpioChip chip;
  SyncLine line(std::make_unique<LibgpiodLineIo>(), strobeOptions(EdgeDetection::kBoth));
  line.start();
  // Half a second of a 30 Hz strobe's two edges, ending now on CLOCK_MONOTONIC (the kernel's stamp clock).
  constexpr int kPulses = 16;
  constexpr std::int64_t kPulseWidthNs = 5 * kNsPerMillisecond;
  const std::int64_t first_ns = monotonicNowNs() - (kPulses - 1) * kStrobePeriodNs - kPulseWidthNs;
  std::vector<std::int64_t> times_ns;
  for (int i = 0; i < kPulses; ++i) {
    const std::int64_t rise_ns = first_ns + i * kStrobePeriodNs;
    chip.emitEdge(static_cast<std::uint64_t>(rise_ns), true);
    chip.emitEdge(static_cast<std::uint64_t>(rise_ns + kPulseWidthNs), false);
    times_ns.push_back(rise_ns);
    times_ns.push_back(rise_ns + kPulseWidthNs);
  }
  std::vector<SyncEdge> edges;
  ASSERT_TRUE(waitFor([&] {
    for (const SyncEdge& edge : popAll(line)) edges.push_back(edge);
    return edges.size() == times_ns.size();
  }));
  for (std::size_t i = 0; i < edges.size(); ++i) {
    EXPECT_EQ(edges[i].t_ns, times_ns[i]) << i;
    EXPECT_EQ(edges[i].rising, i % 2 == 0) << i;
    EXPECT_EQ(edges[i].sequence, i);
  }
  // 32 edges: two per 33.3 ms period (not evenly spaced), over 15 periods + one pulse width.
  const double expected_hz = 31.0 / nsToSeconds(15 * kStrobePeriodNs + kPulseWidthNs);
  ASSERT_TRUE(waitFor([&] { return line.stats().edge_rate_hz > 0.0; }));
  EXPECT_NEAR(line.stats().edge_rate_hz, expected_hz, 1e-6);
  EXPECT_EQ(line.stats().dropped(), 0u);
  line.stop();
  EXPECT_EQ(line.state(), SyncLineState::kClosed);
}

// libgpiod 1.6 reports every event id other than GPIOEVENT_EVENT_RISING_EDGE as a falling edge, so an id the
// uAPI does not define arrives as "falling": with only rising edges requested it is dropped as not requested.
TEST(LibgpiodUmockdev, DropsRealtimeStampsAndEventsNotRequested) {
  UmockdevGpioChip chip;
  SyncLine line(std::make_unique<LibgpiodLineIo>(), strobeOptions());
  line.start();
  timespec realtime{};
  ::clock_gettime(CLOCK_REALTIME, &realtime);
  chip.emitEdge(static_cast<std::uint64_t>(realtime.tv_sec) * kNsPerSecond, true);  // Linux < 5.7
  constexpr std::uint32_t kNoSuchEventId = 7;
  chip.emitEdge(static_cast<std::uint64_t>(monotonicNowNs()), true, kNoSuchEventId);
  chip.emitEdge(static_cast<std::uint64_t>(monotonicNowNs()), true);
  ASSERT_TRUE(waitFor([&] { return line.stats().edges_read == 3; }));
  const SyncLineStats stats = line.stats();
  EXPECT_EQ(stats.clock_mismatch, 1u);
  EXPECT_EQ(stats.bad_event_type, 1u);
  EXPECT_EQ(stats.edges, 1u);
  EXPECT_EQ(line.lastProblem(),
            "gpiochip0 line 3: edge 1 has event type falling, but rising edges were requested (dropped)");
  const std::vector<SyncEdge> edges = popAll(line);
  ASSERT_EQ(edges.size(), 1u);
  EXPECT_EQ(edges[0].sequence, 2u);
}

TEST(LibgpiodUmockdev, AnEventFdThatEndsFailsTheStreamWithTheReason) {
  UmockdevGpioChip chip;
  SyncLine line(std::make_unique<LibgpiodLineIo>(), strobeOptions());
  line.start();
  chip.hangUp();
  ASSERT_TRUE(waitFor([&] { return line.state() != SyncLineState::kRunning; }));
  EXPECT_EQ(line.state(), SyncLineState::kFailed);
  EXPECT_EQ(line.lastError(), "gpiochip0 line 3: reading edge events failed: error (Input/output error)");
  line.stop();
}

}  // namespace
}  // namespace vifusion::gpio_sync
