#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <deque>
#include <random>
#include <vector>

#include "vifusion/clock/sliding_lower_hull.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion::clock {
namespace {

/// True when q lies on or above the segment p–r (p.device < q.device < r.device), exactly.
bool onOrAbove(const ClockPoint& p, const ClockPoint& q, const ClockPoint& r) {
  const Int128 cross = static_cast<Int128>(q.device_ns - p.device_ns) * (r.host_ns - p.host_ns) -
                       static_cast<Int128>(q.host_ns - p.host_ns) * (r.device_ns - p.device_ns);
  return cross <= 0;
}

/// The lower hull by definition, O(n³): a point is a vertex unless it lies on or above the segment of
/// some pair around it. Independent of the monotone chain under test.
std::vector<ClockPoint> bruteForceHull(const std::deque<ClockPoint>& window) {
  std::vector<ClockPoint> vertices;
  for (std::size_t j = 0; j < window.size(); ++j) {
    bool vertex = true;
    for (std::size_t i = 0; i < j && vertex; ++i) {
      for (std::size_t k = j + 1; k < window.size() && vertex; ++k)
        vertex = !onOrAbove(window[i], window[j], window[k]);
    }
    if (vertex) vertices.push_back(window[j]);
  }
  return vertices;
}

void expectSameHull(const SlidingLowerHull& hull, const std::deque<ClockPoint>& window) {
  const std::vector<ClockPoint> expected = bruteForceHull(window);
  ASSERT_EQ(hull.vertexCount(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(hull.vertex(i).device_ns, expected[i].device_ns) << "vertex " << i;
    EXPECT_EQ(hull.vertex(i).host_ns, expected[i].host_ns) << "vertex " << i;
  }
}

TEST(SlidingLowerHull, MatchesBruteForceUnderPushesExpiryAndOverflow) {
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    std::mt19937_64 rng(seed);
    std::exponential_distribution<double> latency(1.0 / 300'000.0);  // 300 µs mean
    std::uniform_int_distribution<int> action(0, 9);
    constexpr std::size_t kCapacity = 40;
    SlidingLowerHull hull(kCapacity);
    std::deque<ClockPoint> window;
    std::int64_t device_ns = 1'000'000'000;
    std::int64_t checks = 0;
    for (int step = 0; step < 600; ++step) {
      if (action(rng) == 0 && !window.empty()) {
        // Expire a random stretch of the oldest points (sometimes all but the newest).
        const std::int64_t cut_ns =
            window.front().device_ns +
            static_cast<std::int64_t>(
                rng() % static_cast<std::uint64_t>(window.back().device_ns - window.front().device_ns + 1));
        hull.expireBefore(cut_ns);
        while (!window.empty() && window.front().device_ns < cut_ns) window.pop_front();
      } else {
        device_ns += 2'222'222;  // 450 Hz
        // 50 ppm of skew on top, so the hull is tilted as in use.
        const ClockPoint p{device_ns, device_ns + device_ns / 20'000 + static_cast<std::int64_t>(latency(rng))};
        hull.push(p);
        window.push_back(p);
        if (window.size() > kCapacity) window.pop_front();  // full: the oldest goes
      }
      ASSERT_EQ(hull.size(), window.size());
      if (window.empty()) continue;
      EXPECT_EQ(hull.oldest().device_ns, window.front().device_ns);
      EXPECT_EQ(hull.newest().device_ns, window.back().device_ns);
      expectSameHull(hull, window);
      ++checks;
    }
    EXPECT_GT(checks, 500);
  }
}

TEST(SlidingLowerHull, CollinearPointsLeaveOnlyTheEnds) {
  // A jitter-free link: every point on one line. Exact arithmetic keeps just the two ends, even with
  // 2^60-ns coordinates where a double would round the cross product.
  SlidingLowerHull hull(1000);
  const std::int64_t base_ns = std::int64_t{1} << 60;
  for (std::int64_t i = 0; i < 1000; ++i) hull.push({base_ns + 1'000'003 * i, base_ns + 7 + 1'000'053 * i});
  ASSERT_EQ(hull.vertexCount(), 2u);
  EXPECT_EQ(hull.vertex(0).device_ns, base_ns);
  EXPECT_EQ(hull.vertex(1).device_ns, base_ns + 1'000'003 * 999);
  // Expiring the first vertex brings the next point in as the new first vertex.
  hull.expireBefore(base_ns + 1);
  ASSERT_EQ(hull.vertexCount(), 2u);
  EXPECT_EQ(hull.vertex(0).device_ns, base_ns + 1'000'003);
  // One point 1 ns under the line in the middle becomes a vertex.
  SlidingLowerHull dented(10);
  for (std::int64_t i = 0; i < 9; ++i) dented.push({base_ns + 1000 * i, base_ns + 1001 * i - (i == 4 ? 1 : 0)});
  ASSERT_EQ(dented.vertexCount(), 3u);
  EXPECT_EQ(dented.vertex(1).device_ns, base_ns + 4000);
}

TEST(SlidingLowerHull, EdgeMeanAndSupport) {
  SlidingLowerHull hull(8);
  // A V-shaped set in host − device: vertices at device 0, 40, 100 (host offsets 50, 0, 30).
  hull.push({0, 50});
  hull.push({20, 20 + 40});
  hull.push({40, 40});
  hull.push({70, 70 + 20});
  hull.push({100, 130});
  ASSERT_EQ(hull.vertexCount(), 3u);
  EXPECT_EQ(hull.edgeAt(-5), 0u);
  EXPECT_EQ(hull.edgeAt(39), 0u);
  EXPECT_EQ(hull.edgeAt(40), 1u);
  EXPECT_EQ(hull.edgeAt(1000), 1u);
  EXPECT_EQ(hull.supportingVertex(0.0), 1u);   // lowest host − device: device 40
  EXPECT_EQ(hull.supportingVertex(-2.0), 0u);  // steeply falling line touches the left end
  EXPECT_EQ(hull.supportingVertex(2.0), 2u);   // steeply rising line touches the right end
  hull.clear();
  EXPECT_TRUE(hull.empty());
  EXPECT_EQ(hull.vertexCount(), 0u);
}

TEST(SlidingLowerHull, RejectsTooSmallCapacity) {
  test::expectError([] { SlidingLowerHull hull(1); }, "capacity = 1 points must be >= 2");
}

}  // namespace
}  // namespace vifusion::clock
