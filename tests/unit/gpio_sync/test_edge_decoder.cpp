#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "vifusion/core/time.hpp"
#include "vifusion/gpio_sync/edge_decoder.hpp"

namespace vifusion::gpio_sync {
namespace {

constexpr std::int64_t kStartNs = 100 * kNsPerSecond;  // CLOCK_MONOTONIC: 100 s after boot
constexpr std::int64_t kStrobePeriodNs = 33'333'333;
/// Where CLOCK_REALTIME was in 2026 [ns since 1970]: what Linux < 5.7 puts into a line event.
constexpr std::int64_t kRealtimeStampNs = 1'780'000'000 * kNsPerSecond;

struct DecoderFixture {
  explicit DecoderFixture(SyncLineOptions options_in = {}, std::size_t ring_capacity = 64)
      : options(withLine(options_in)), ring(ring_capacity), decoder("gpiochip0 line 17", options, ring, problems) {}

  static SyncLineOptions withLine(SyncLineOptions options) {
    options.line_offset = 17;
    return options;
  }

  std::vector<SyncEdge> popAll() {
    std::vector<SyncEdge> out;
    SyncEdge edge;
    while (ring.tryPop(edge)) out.push_back(edge);
    return out;
  }

  SyncLineOptions options;
  SpscRing<SyncEdge> ring;
  ProblemNote problems;
  EdgeDecoder decoder;
};

TEST(EdgeDecoder, PassesGoodEdgesWithTheirTimesAndConsecutiveSequenceNumbers) {
  DecoderFixture f;
  std::vector<LineEvent> events;
  for (int i = 0; i < 10; ++i) events.push_back({kStartNs + i * kStrobePeriodNs, EdgeType::kRising});
  f.decoder.decode(events, events.back().t_ns + kNsPerMicrosecond);

  const std::vector<SyncEdge> edges = f.popAll();
  ASSERT_EQ(edges.size(), 10u);
  for (std::size_t i = 0; i < edges.size(); ++i) {
    EXPECT_EQ(edges[i].t_ns, kStartNs + static_cast<std::int64_t>(i) * kStrobePeriodNs);
    EXPECT_TRUE(edges[i].rising);
    EXPECT_EQ(edges[i].sequence, i);
  }
  const SyncLineStats stats = f.decoder.stats();
  EXPECT_EQ(stats.edges_read, 10u);
  EXPECT_EQ(stats.edges, 10u);
  EXPECT_EQ(stats.dropped(), 0u);
  EXPECT_EQ(stats.last_edge_t_ns, kStartNs + 9 * kStrobePeriodNs);
  EXPECT_TRUE(f.problems.text().empty());
}

TEST(EdgeDecoder, DropsAnEdgeThatGoesBackInTimeAndLeavesAGapInTheSequence) {
  DecoderFixture f;
  const std::vector<LineEvent> events = {{kStartNs, EdgeType::kRising},
                                         {kStartNs + 2 * kNsPerMillisecond, EdgeType::kRising},
                                         {kStartNs + kNsPerMillisecond / 2, EdgeType::kRising},
                                         {kStartNs + 3 * kNsPerMillisecond, EdgeType::kRising}};
  f.decoder.decode(events, kStartNs + 4 * kNsPerMillisecond);

  const std::vector<SyncEdge> edges = f.popAll();
  ASSERT_EQ(edges.size(), 3u);
  EXPECT_EQ(edges[1].sequence, 1u);
  EXPECT_EQ(edges[2].sequence, 3u);
  EXPECT_EQ(edges[2].t_ns, kStartNs + 3 * kNsPerMillisecond);
  EXPECT_EQ(f.decoder.stats().time_backwards, 1u);
  EXPECT_EQ(f.problems.text(), "gpiochip0 line 17: edge 2 time goes backwards by 1.500000 ms (dropped)");
}

TEST(EdgeDecoder, EqualTimestampsAreNotDisorder) {
  DecoderFixture f;
  const std::vector<LineEvent> events = {{kStartNs, EdgeType::kRising}, {kStartNs, EdgeType::kRising}};
  f.decoder.decode(events, kStartNs);
  EXPECT_EQ(f.decoder.stats().edges, 2u);
  EXPECT_EQ(f.decoder.stats().time_backwards, 0u);
}

TEST(EdgeDecoder, DropsEventTypesThatWereNotRequested) {
  DecoderFixture rising_only;  // the default request
  const std::vector<LineEvent> events = {{kStartNs, EdgeType::kRising},
                                         {kStartNs + 1, EdgeType::kFalling},
                                         {kStartNs + 2, EdgeType::kUnknown},
                                         {kStartNs + 3, EdgeType::kRising}};
  rising_only.decoder.decode(events, kStartNs + kNsPerMillisecond);
  EXPECT_EQ(rising_only.decoder.stats().edges, 2u);
  EXPECT_EQ(rising_only.decoder.stats().bad_event_type, 2u);
  EXPECT_EQ(rising_only.problems.text(),
            "gpiochip0 line 17: edge 2 has event type unknown, but rising edges were requested (dropped)");

  SyncLineOptions both;
  both.edges = EdgeDetection::kBoth;
  DecoderFixture both_edges(both);
  both_edges.decoder.decode(events, kStartNs + kNsPerMillisecond);
  const std::vector<SyncEdge> edges = both_edges.popAll();
  ASSERT_EQ(edges.size(), 3u);
  EXPECT_TRUE(edges[0].rising);
  EXPECT_FALSE(edges[1].rising);
  EXPECT_EQ(edges[1].t_ns, kStartNs + 1);
  EXPECT_EQ(both_edges.decoder.stats().bad_event_type, 1u);

  SyncLineOptions falling;
  falling.edges = EdgeDetection::kFalling;
  DecoderFixture falling_only(falling);
  falling_only.decoder.decode(std::vector<LineEvent>{events[0]}, kStartNs + kNsPerMillisecond);
  EXPECT_EQ(falling_only.problems.text(),
            "gpiochip0 line 17: edge 0 has event type rising, but falling edges were requested (dropped)");
}

TEST(EdgeDecoder, DropsTimestampsThatAreNotTimes) {
  DecoderFixture f;
  f.decoder.decode(std::vector<LineEvent>{{kUnrepresentableTimeNs, EdgeType::kRising}}, kStartNs);
  EXPECT_EQ(f.problems.text(), "gpiochip0 line 17: edge 0 timestamp does not fit in int64 ns (dropped)");
  f.decoder.decode(std::vector<LineEvent>{{-5, EdgeType::kRising}}, kStartNs);
  EXPECT_EQ(f.problems.text(), "gpiochip0 line 17: edge 1 timestamp -5 ns is negative (dropped)");
  EXPECT_EQ(f.decoder.stats().bad_timestamp, 2u);
  EXPECT_EQ(f.decoder.stats().edges, 0u);
}

TEST(EdgeDecoder, DropsRealtimeStampsOfOldKernelsAndSaysSo) {
  DecoderFixture f;
  const std::vector<LineEvent> events = {{kRealtimeStampNs, EdgeType::kRising},
                                         {kStartNs + EdgeDecoder::kClockSlackNs / 2, EdgeType::kRising}};
  f.decoder.decode(events, kStartNs);
  const SyncLineStats stats = f.decoder.stats();
  EXPECT_EQ(stats.clock_mismatch, 1u);
  EXPECT_EQ(stats.edges, 1u);  // within the slack: kept
  const std::string problem = f.problems.text();
  EXPECT_NE(problem.find("gpiochip0 line 17: edge 0 timestamp is 1779999900.000000 s after it was read"),
            std::string::npos)
      << problem;
  EXPECT_NE(problem.find("Linux < 5.7 stamps CLOCK_REALTIME"), std::string::npos) << problem;
}

TEST(EdgeDecoder, CountsOverrunsWhenTheRingIsFullAndTheSequenceShowsTheLoss) {
  DecoderFixture f({}, 4);
  std::vector<LineEvent> events;
  for (int i = 0; i < 6; ++i) events.push_back({kStartNs + i * kStrobePeriodNs, EdgeType::kRising});
  f.decoder.decode(events, events.back().t_ns);
  EXPECT_EQ(f.decoder.stats().edges, 4u);
  EXPECT_EQ(f.decoder.stats().overruns, 2u);
  EXPECT_EQ(f.ring.overruns(), 2u);
  std::vector<SyncEdge> edges = f.popAll();
  ASSERT_EQ(edges.size(), 4u);
  EXPECT_EQ(edges.back().sequence, 3u);

  f.decoder.decode(std::vector<LineEvent>{{kStartNs + 6 * kStrobePeriodNs, EdgeType::kRising}},
                   kStartNs + 6 * kStrobePeriodNs);
  edges = f.popAll();
  ASSERT_EQ(edges.size(), 1u);
  EXPECT_EQ(edges[0].sequence, 6u);  // 4 and 5 were lost to the full ring
}

TEST(EdgeDecoder, PublishesTheRateAndResetStartsANewStream) {
  DecoderFixture f;
  std::vector<LineEvent> events;
  for (int i = 0; i < 31; ++i) events.push_back({kStartNs + i * kStrobePeriodNs, EdgeType::kRising});
  f.decoder.decode(events, events.back().t_ns);
  EXPECT_EQ(f.decoder.stats().edge_rate_hz, 0.0);  // published only by publishRate()
  f.decoder.publishRate(events.back().t_ns);
  EXPECT_NEAR(f.decoder.stats().edge_rate_hz, 30.0, 1e-5);

  f.decoder.reset();
  EXPECT_EQ(f.decoder.stats().edge_rate_hz, 0.0);
  f.popAll();
  // A re-opened line may start earlier on the clock (never in practice, but nothing is compared across).
  f.decoder.decode(std::vector<LineEvent>{{kStartNs, EdgeType::kRising}}, kStartNs);
  const std::vector<SyncEdge> edges = f.popAll();
  ASSERT_EQ(edges.size(), 1u);
  EXPECT_EQ(edges[0].sequence, 0u);
  EXPECT_EQ(f.decoder.stats().edges_read, 32u);  // counters stay across reset
  EXPECT_EQ(f.decoder.stats().time_backwards, 0u);
}

}  // namespace
}  // namespace vifusion::gpio_sync
