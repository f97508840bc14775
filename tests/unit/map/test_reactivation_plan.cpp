// The host's plan that takes reactivated surfels out of the inactive prefix (surfel_reactivation.hpp
// planReactivationMoves) and its CPU mover: a hand-checked case, and random maps and id images checked from first
// principles — the prefix shrinks by the number of distinct marked slots, every marked surfel ends above it, every
// unmarked one of the old prefix below it, nothing is lost or duplicated, and both arrays hold the same prefix.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <set>
#include <vector>

#include "vifusion/map/prediction_cpu.hpp"
#include "vifusion/map/surfel_reactivation.hpp"

namespace vifusion::map {
namespace {

// Prefix [0, 10), ids 2, 8 (twice), 9 and others at or above the prefix's end or none. Three distinct slots: the
// prefix ends at 7; slot 2 swaps with 7 (the only unmarked slot in [7, 10)); 8 and 9 are already above the end.
TEST(ReactivationPlan, MovesEachMarkedPrefixSlotAboveTheShrunkPrefixOnce) {
  const std::vector<std::uint32_t> ids = {8, kNoSurfel, 2, 12, 9, 8, 10, kNoSurfel};
  std::vector<std::uint32_t> scratch(ids.size());
  std::vector<ReactivationMove> moves(ids.size());
  const ReactivationPlan plan = planReactivationMoves(ids, 10, scratch, moves);
  EXPECT_EQ(plan.active_begin, 7u);
  ASSERT_EQ(plan.moves, 1u);
  EXPECT_EQ(moves[0].marked_slot, 2u);
  EXPECT_EQ(moves[0].unmarked_slot, 7u);

  const ReactivationPlan none = planReactivationMoves(ids, 0, scratch, moves);
  EXPECT_EQ(none.active_begin, 0u) << "the whole map is visited anyway";
  EXPECT_EQ(none.moves, 0u);
}

TEST(ReactivationPlan, RandomMapsKeepEverySurfelAndTheMarkedOnesLeaveThePrefix) {
  constexpr int kMaps = 200;
  std::mt19937 random(7);
  for (int m = 0; m < kMaps; ++m) {
    const std::uint32_t count = 1 + random() % 400;
    const std::uint32_t active_begin = random() % (count + 1);
    const std::size_t pixels = 1 + random() % 300;
    std::vector<std::uint32_t> ids(pixels);
    for (std::uint32_t& id : ids) id = random() % 4 == 0 ? kNoSurfel : random() % count;

    // Surfel i carries its original slot in its creation frame, so where it went is visible.
    std::vector<Surfel> current(count), other(count);
    for (std::uint32_t i = 0; i < count; ++i) current[i].colour_times.y() = other[i].colour_times.y() = float(i);
    std::vector<std::uint32_t> scratch(pixels);
    std::vector<ReactivationMove> moves(pixels);
    const ReactivationPlan plan = planReactivationMoves(ids, active_begin, scratch, moves);
    applyReactivationMovesCpu(current, other, std::span(moves.data(), plan.moves));

    std::set<std::uint32_t> marked;
    for (const std::uint32_t id : ids) {
      if (id < active_begin) marked.insert(id);
    }
    ASSERT_EQ(plan.active_begin, active_begin - marked.size()) << "map " << m;
    std::vector<std::uint32_t> seen;
    for (std::uint32_t slot = 0; slot < count; ++slot) {
      const auto original = static_cast<std::uint32_t>(current[slot].colour_times.y());
      seen.push_back(original);
      if (slot < plan.active_begin) {
        EXPECT_FALSE(marked.count(original)) << "map " << m << ": marked surfel " << original << " left in the prefix";
        EXPECT_EQ(other[slot].colour_times.y(), current[slot].colour_times.y()) << "map " << m << ": prefixes differ";
      } else if (slot < active_begin) {
        EXPECT_TRUE(marked.count(original)) << "map " << m << ": unmarked surfel " << original << " left the prefix";
      } else {
        EXPECT_EQ(original, slot) << "map " << m << ": the active range is not touched";
      }
    }
    std::sort(seen.begin(), seen.end());
    for (std::uint32_t i = 0; i < count; ++i) ASSERT_EQ(seen[i], i) << "map " << m << ": lost or duplicated";
  }
}

}  // namespace
}  // namespace vifusion::map
