#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "expect_error.hpp"
#include "vifusion/eval/associate.hpp"

namespace vifusion::eval {
namespace {

using test::expectError;
constexpr std::int64_t kMs = kNsPerMillisecond;

std::vector<std::pair<std::size_t, std::size_t>> pairsOf(const std::vector<Match>& matches) {
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (const Match& m : matches) pairs.emplace_back(m.index_a, m.index_b);
  return pairs;
}

using Pairs = std::vector<std::pair<std::size_t, std::size_t>>;

TEST(Associate, MatchesWithinWindowSortedByTime) {
  const std::vector<std::int64_t> a = {0, 100 * kMs, 200 * kMs, 300 * kMs};
  const std::vector<std::int64_t> b = {5 * kMs, 195 * kMs, 290 * kMs, 400 * kMs};
  // 100 ms has nothing within 20 ms; 400 ms neither.
  EXPECT_EQ(pairsOf(associate(a, b)), (Pairs{{0, 0}, {2, 1}, {3, 2}}));
}

TEST(Associate, BoundaryIsExclusive) {
  const std::vector<std::int64_t> a = {0, 1000 * kMs};
  const std::vector<std::int64_t> b = {20 * kMs, 1000 * kMs + 20 * kMs - 1};
  // associate.py keeps |Δt| < max_difference: exactly 20 ms is out, 1 ns less is in.
  EXPECT_EQ(pairsOf(associate(a, b)), (Pairs{{1, 1}}));
}

TEST(Associate, EachStampUsedOnceClosestFirst) {
  // b[0] and b[1] both want a[0]; b[1] is closer and wins; b[0] falls back to nothing in range.
  const std::vector<std::int64_t> a = {100 * kMs, 200 * kMs};
  const std::vector<std::int64_t> b = {90 * kMs, 98 * kMs, 185 * kMs};
  EXPECT_EQ(pairsOf(associate(a, b)), (Pairs{{0, 1}, {1, 2}}));
}

TEST(Associate, GreedyNotGloballyOptimal) {
  // a[1] (10 ms) pairs with b[0] (11 ms) first (1 ms); a[0] (0) then cannot use b[0] and takes nothing
  // although {a0-b0, a1-b1} would match both — the documented associate.py behaviour.
  const std::vector<std::int64_t> a = {0, 10 * kMs};
  const std::vector<std::int64_t> b = {11 * kMs, 40 * kMs};
  EXPECT_EQ(pairsOf(associate(a, b)), (Pairs{{1, 0}}));
}

TEST(Associate, TiesBrokenByEarlierStampsAsPythonTupleSort) {
  // a[0]=0 and a[1]=20 ms are both 10 ms from b[0]=10 ms: the tie goes to the smaller t_a.
  const std::vector<std::int64_t> a = {0, 20 * kMs};
  const std::vector<std::int64_t> b = {10 * kMs};
  EXPECT_EQ(pairsOf(associate(a, b)), (Pairs{{0, 0}}));
  // b[0] and b[1] equally far from a[0]: the smaller t_b wins.
  const std::vector<std::int64_t> a2 = {10 * kMs};
  const std::vector<std::int64_t> b2 = {0, 20 * kMs};
  EXPECT_EQ(pairsOf(associate(a2, b2)), (Pairs{{0, 0}}));
}

TEST(Associate, OffsetShiftsSecondList) {
  const std::vector<std::int64_t> a = {1000 * kMs};
  const std::vector<std::int64_t> b = {500 * kMs};
  EXPECT_TRUE(associate(a, b).empty());
  EXPECT_EQ(pairsOf(associate(a, b, 20 * kMs, 495 * kMs)), (Pairs{{0, 0}}));
}

TEST(Associate, NoOverlapGivesEmptyResult) {
  const std::vector<std::int64_t> a = {0, 10 * kMs};
  const std::vector<std::int64_t> b = {5000 * kMs, 5010 * kMs};
  EXPECT_TRUE(associate(a, b).empty());
  EXPECT_TRUE(associate(std::vector<std::int64_t>{}, b).empty());
}

TEST(Associate, DuplicateOrUnsortedStampsAreRejected) {
  const std::vector<std::int64_t> dup = {0, 10 * kMs, 10 * kMs};
  const std::vector<std::int64_t> ok = {0};
  expectError([&] { associate(dup, ok); }, "first stamps must strictly increase; index 2");
  expectError([&] { associate(ok, dup); }, "second stamps must strictly increase; index 2");
  expectError([&] { associate(ok, ok, 0); }, "max_difference must be positive");
}

}  // namespace
}  // namespace vifusion::eval
