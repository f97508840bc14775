// SyncLine's driver thread against a scripted line: the real thread, decoder, ring and rate logic; only the
// GPIO calls are played by ScriptedLineIo.

#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "vifusion/core/time.hpp"
#include "vifusion/gpio_sync/scripted_line_io.hpp"
#include "vifusion/gpio_sync/sync_line.hpp"
#include "vifusion/test/counting_allocations.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion::gpio_sync {
namespace {

constexpr std::int64_t kStartNs = 100 * kNsPerSecond;
constexpr std::int64_t kStrobePeriodNs = 33'333'333;
/// How long a test waits for the driver thread before it fails [real time]; never reached when passing.
constexpr auto kPatience = std::chrono::seconds(5);

/// Polls `done` every millisecond until it holds or kPatience passes; true when it held. Allocates nothing.
bool waitUntil(const std::function<bool()>& done) {
  const auto deadline = std::chrono::steady_clock::now() + kPatience;
  while (!done()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

struct LineFixture {
  explicit LineFixture(SyncLineOptions options_in = defaultOptions()) : options(options_in) {
    auto io = std::make_unique<ScriptedLineIo>(8192, kStartNs);
    script = io.get();
    line = std::make_unique<SyncLine>(std::move(io), options);
  }

  static SyncLineOptions defaultOptions() {
    SyncLineOptions options;
    options.chip = "gpiochip2";
    options.line_offset = 3;
    options.wait_timeout_ms = 10;  // stop() within 10 ms; cheap with a condition-variable wait
    return options;
  }

  /// Queues `count` rising edges a strobe period apart, continuing from the last one queued.
  void pushStrobes(int count) {
    for (int i = 0; i < count; ++i, next_ns += kStrobePeriodNs) script->pushEdge(next_ns);
  }

  std::vector<SyncEdge> popAll() {
    std::vector<SyncEdge> out;
    SyncEdge edge;
    while (line->edgeRing().tryPop(edge)) out.push_back(edge);
    return out;
  }

  SyncLineOptions options;
  ScriptedLineIo* script = nullptr;  // owned by `line`
  std::unique_ptr<SyncLine> line;
  std::int64_t next_ns = kStartNs;
};

TEST(SyncLine, OpensTheConfiguredLineAndDeliversEdgesInOrder) {
  SyncLineOptions options = LineFixture::defaultOptions();
  options.edges = EdgeDetection::kBoth;
  LineFixture f(options);
  EXPECT_EQ(f.line->lineName(), "gpiochip2 line 3");
  f.line->start();
  EXPECT_TRUE(f.script->isOpen());
  EXPECT_EQ(f.script->openedChip(), "gpiochip2");
  EXPECT_EQ(f.script->openedLine(), 3u);
  EXPECT_EQ(f.script->openedEdges(), EdgeDetection::kBoth);
  EXPECT_EQ(f.line->state(), SyncLineState::kRunning);

  // 100 edges: more than one read's worth (16), alternating rising/falling as a strobe pulse gives them.
  constexpr int kEdges = 100;
  for (int i = 0; i < kEdges; ++i) {
    f.script->pushEdge(kStartNs + i * kNsPerMillisecond, i % 2 == 0 ? EdgeType::kRising : EdgeType::kFalling);
  }
  std::vector<SyncEdge> edges;
  ASSERT_TRUE(waitUntil([&] {
    for (const SyncEdge& edge : f.popAll()) edges.push_back(edge);
    return edges.size() == kEdges;
  }));
  for (std::size_t i = 0; i < edges.size(); ++i) {
    EXPECT_EQ(edges[i].t_ns, kStartNs + static_cast<std::int64_t>(i) * kNsPerMillisecond);
    EXPECT_EQ(edges[i].rising, i % 2 == 0);
    EXPECT_EQ(edges[i].sequence, i);
  }
  EXPECT_EQ(f.script->eventsRead(), static_cast<std::size_t>(kEdges));

  f.line->stop();
  EXPECT_FALSE(f.script->isOpen());
  EXPECT_EQ(f.line->state(), SyncLineState::kClosed);
  const SyncLineStats stats = f.line->stats();
  EXPECT_EQ(stats.state, SyncLineState::kClosed);
  EXPECT_EQ(stats.edges_read, 100u);
  EXPECT_EQ(stats.edges, 100u);
  EXPECT_EQ(stats.dropped(), 0u);
}

TEST(SyncLine, CountsOverrunsWhenTheConsumerDoesNotPop) {
  SyncLineOptions options = LineFixture::defaultOptions();
  options.ring_capacity = 8;
  LineFixture f(options);
  f.line->start();
  f.pushStrobes(20);
  ASSERT_TRUE(waitUntil([&] { return f.line->stats().edges_read == 20; }));
  const SyncLineStats stats = f.line->stats();
  EXPECT_EQ(stats.edges, 8u);
  EXPECT_EQ(stats.overruns, 12u);
  const std::vector<SyncEdge> edges = f.popAll();
  ASSERT_EQ(edges.size(), 8u);
  EXPECT_EQ(edges.front().sequence, 0u);
  EXPECT_EQ(edges.back().sequence, 7u);  // the ring drops the newest: the consumer keeps a gap-free prefix
}

TEST(SyncLine, DropsAnEdgeGoingBackInTimeWithAMessageNamingTheLine) {
  LineFixture f;
  f.line->start();
  f.script->pushEdge(kStartNs + 10 * kNsPerMillisecond);
  f.script->pushEdge(kStartNs + 8 * kNsPerMillisecond);
  f.script->pushEdge(kStartNs + 11 * kNsPerMillisecond);
  ASSERT_TRUE(waitUntil([&] { return f.line->stats().edges_read == 3; }));
  EXPECT_EQ(f.line->stats().time_backwards, 1u);
  EXPECT_EQ(f.line->stats().edges, 2u);
  EXPECT_EQ(f.line->lastProblem(), "gpiochip2 line 3: edge 1 time goes backwards by 2.000000 ms (dropped)");
}

TEST(SyncLine, DropsEdgesStampedOnTheRealtimeClock) {
  LineFixture f;
  f.script->setNowNs(kStartNs);  // CLOCK_MONOTONIC 100 s after boot, pinned
  f.line->start();
  f.script->pushEdge(1'780'000'000 * kNsPerSecond);
  ASSERT_TRUE(waitUntil([&] { return f.line->stats().edges_read == 1; }));
  EXPECT_EQ(f.line->stats().clock_mismatch, 1u);
  EXPECT_EQ(f.line->stats().edges, 0u);
  EXPECT_NE(f.line->lastProblem().find("gpiochip2 line 3: edge 0"), std::string::npos);
  EXPECT_NE(f.line->lastProblem().find("Linux < 5.7"), std::string::npos);
}

TEST(SyncLine, ReportsTheEdgeRateAndItsDecayOnASilentLine) {
  SyncLineOptions options = LineFixture::defaultOptions();
  options.rate_window_ns = 500 * kNsPerMillisecond;
  LineFixture f(options);
  f.line->start();
  f.pushStrobes(31);  // one second of a 30 Hz strobe
  ASSERT_TRUE(waitUntil([&] { return f.line->stats().edges_read == 31; }));
  ASSERT_TRUE(waitUntil([&] { return f.line->stats().edge_rate_hz > 0.0; }));
  EXPECT_NEAR(f.line->stats().edge_rate_hz, 30.0, 1e-5);
  EXPECT_EQ(f.line->stats().last_edge_t_ns, kStartNs + 30 * kStrobePeriodNs);
  // Each timed-out wait moves the scripted clock by 10 ms: after 500 ms of silence the window is empty.
  ASSERT_TRUE(waitUntil([&] { return f.line->stats().edge_rate_hz == 0.0; }));
}

TEST(SyncLine, AVanishedChipEndsTheStreamAsGoneAndStartReopens) {
  LineFixture f;
  f.line->start();
  f.pushStrobes(5);
  f.script->failAfterQueued(LineStatus::kGone, "No such device");
  ASSERT_TRUE(waitUntil([&] { return f.line->state() == SyncLineState::kGone; }));
  EXPECT_EQ(f.line->stats().edges, 5u);  // the edges before the chip went are delivered
  EXPECT_EQ(f.line->lastError(), "gpiochip2 line 3: waiting for edge events failed: gone (No such device)");
  f.line->stop();
  EXPECT_EQ(f.line->state(), SyncLineState::kGone);  // stop() keeps why the stream ended
  EXPECT_FALSE(f.script->isOpen());

  f.script->failAfterQueued(LineStatus::kEvents, "");  // the chip is back
  f.popAll();
  f.line->start();
  EXPECT_EQ(f.script->openCount(), 2);
  EXPECT_EQ(f.line->state(), SyncLineState::kRunning);
  EXPECT_TRUE(f.line->lastError().empty());
  f.pushStrobes(1);
  std::vector<SyncEdge> edges;
  ASSERT_TRUE(waitUntil([&] {
    edges = f.popAll();
    return !edges.empty();
  }));
  EXPECT_EQ(edges[0].sequence, 0u);  // a new stream
}

TEST(SyncLine, AReadErrorEndsTheStreamAsFailed) {
  LineFixture f;
  f.line->start();
  f.script->failAfterQueued(LineStatus::kError, "Input/output error");
  ASSERT_TRUE(waitUntil([&] { return f.line->state() == SyncLineState::kFailed; }));
  EXPECT_EQ(f.line->lastError(), "gpiochip2 line 3: waiting for edge events failed: error (Input/output error)");
}

TEST(SyncLine, StartPassesTheOpenErrorOnAndStaysClosed) {
  LineFixture f;
  f.script->failOpen("gpiochip2: no such GPIO chip (/dev/gpiochip2: No such file or directory)");
  test::expectError([&] { f.line->start(); }, "gpiochip2: no such GPIO chip");
  EXPECT_EQ(f.line->state(), SyncLineState::kClosed);
  f.line->stop();  // safe after a failed start
}

TEST(SyncLine, StopIsSeenWithinTheWaitTimeout) {
  SyncLineOptions options = LineFixture::defaultOptions();
  options.wait_timeout_ms = 50;
  LineFixture f(options);
  f.line->start();
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const auto before = std::chrono::steady_clock::now();
  f.line->stop();
  const auto stop_ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - before).count();
  EXPECT_LE(stop_ms, 4 * options.wait_timeout_ms);  // one wait at most, with room for a loaded machine
}

TEST(SyncLine, RejectsANullLineAndBadOptions) {
  test::expectError([] { SyncLine line(nullptr); }, "SyncLine: io is null");
  SyncLineOptions options;
  options.ring_capacity = 0;
  test::expectError([&] { SyncLine line(std::make_unique<ScriptedLineIo>(), options); },
                    "SyncLineOptions.ring_capacity must be >= 1, got 0");
}

TEST(SyncLine, SteadyStreamingAllocatesNothing) {
  SyncLineOptions options = LineFixture::defaultOptions();
  options.ring_capacity = 4096;  // room for every edge: this test is about allocation, not overruns
  LineFixture f(options);
  f.line->start();
  f.pushStrobes(50);  // warm-up: first wait, first read, first publish
  ASSERT_TRUE(waitUntil([&] { return f.line->stats().edges_read == 50; }));
  f.popAll();

  const std::uint64_t before = test::heapAllocationCount();
  constexpr std::uint64_t kEdges = 2000;
  std::uint64_t popped = 0;
  SyncEdge edge;
  for (std::uint64_t i = 0; i < kEdges; ++i, f.next_ns += kStrobePeriodNs) {
    f.script->pushEdge(f.next_ns);  // into storage reserved at construction
    while (f.line->edgeRing().tryPop(edge)) ++popped;
  }
  const auto deadline = std::chrono::steady_clock::now() + kPatience;
  while (popped < kEdges && std::chrono::steady_clock::now() < deadline) {
    while (f.line->edgeRing().tryPop(edge)) ++popped;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  const std::uint64_t allocations = test::heapAllocationCount() - before;
  EXPECT_EQ(popped, kEdges);
  EXPECT_EQ(allocations, 0u);
  EXPECT_EQ(f.line->stats().dropped(), 0u);
}

}  // namespace
}  // namespace vifusion::gpio_sync
