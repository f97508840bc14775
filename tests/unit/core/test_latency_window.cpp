// LatencyWindow: nearest-rank percentiles of the newest samples, the oldest replaced, bad samples kept out.

#include <gtest/gtest.h>

#include <cmath>

#include "vifusion/core/latency_window.hpp"

namespace vifusion {
namespace {

TEST(LatencyWindow, EmptyWindowSummarisesToZero) {
  const LatencySummary s = LatencyWindow().summary();
  EXPECT_EQ(s.samples, 0u);
  EXPECT_EQ(s.p50_ms, 0.0f);
  EXPECT_EQ(s.max_ms, 0.0f);
}

TEST(LatencyWindow, NearestRankPercentilesOfOneToAHundred) {
  LatencyWindow window;
  // 1..100 in a scrambled order: the summary does not depend on it.
  for (int i = 0; i < 100; ++i) window.add(static_cast<float>((i * 37) % 100 + 1));
  const LatencySummary s = window.summary();
  EXPECT_EQ(s.samples, 100u);
  EXPECT_EQ(s.p50_ms, 50.0f);  // rank ⌈0.5·100⌉ = 50
  EXPECT_EQ(s.p99_ms, 99.0f);  // rank 99
  EXPECT_EQ(s.max_ms, 100.0f);
  EXPECT_EQ(s.last_ms, static_cast<float>((99 * 37) % 100 + 1));
}

TEST(LatencyWindow, KeepsTheNewestSamplesOnly) {
  LatencyWindow window;
  for (std::size_t i = 0; i < LatencyWindow::kCapacity; ++i) window.add(1000.0f);  // an old stall
  for (std::size_t i = 0; i < LatencyWindow::kCapacity; ++i) window.add(static_cast<float>(i % 10));
  const LatencySummary s = window.summary();
  EXPECT_EQ(s.samples, LatencyWindow::kCapacity);
  EXPECT_EQ(s.max_ms, 9.0f);
  EXPECT_EQ(s.p99_ms, 9.0f);
  EXPECT_EQ(s.p50_ms, 4.0f);  // 30 of each of 0..9: rank 150 is the last 4
}

TEST(LatencyWindow, OneSlowFrameInAHundredIsTheMaximumNotTheP99) {
  LatencyWindow window;
  for (int i = 0; i < 99; ++i) window.add(20.0f);
  window.add(500.0f);
  const LatencySummary s = window.summary();
  EXPECT_EQ(s.p99_ms, 20.0f);
  EXPECT_EQ(s.max_ms, 500.0f);
  window.add(480.0f);  // two in 101: above 1 %
  EXPECT_EQ(window.summary().p99_ms, 480.0f);
}

TEST(LatencyWindow, NegativeAndNanSamplesAreCountedAndLeftOut) {
  LatencyWindow window;
  window.add(5.0f);
  window.add(-1.0f);
  window.add(std::nanf(""));
  EXPECT_EQ(window.rejected(), 2u);
  EXPECT_EQ(window.summary().samples, 1u);
  EXPECT_EQ(window.summary().max_ms, 5.0f);
}

}  // namespace
}  // namespace vifusion
