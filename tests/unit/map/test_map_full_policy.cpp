// The map-full policy's age limit (maintenance_cpu.hpp nextEvictionAge): off while the map is below
// its full mark; the first full frame evicts what the newer half of the run did not update, each
// further full frame halves the age down to the time window, and room in the map switches it off.

#include <gtest/gtest.h>

#include "vifusion/map/maintenance_cpu.hpp"

namespace vifusion::map {
namespace {

constexpr std::uint32_t kFull = 1'900'000;  // 0.95 × 2 M
constexpr std::uint32_t kWindow = 200;

TEST(MapFullPolicy, EvictsNothingForAgeBelowTheFullMark) {
  EXPECT_EQ(nextEvictionAge(kNoAgeEviction, kFull, kFull, 1300, kWindow), kNoAgeEviction);
  EXPECT_EQ(nextEvictionAge(300, 1'000'000, kFull, 1300, kWindow), kNoAgeEviction) << "room again: off";
}

TEST(MapFullPolicy, HalvesTheAgeWhileTheMapStaysFullDownToTheTimeWindow) {
  std::uint32_t age = kNoAgeEviction;
  std::uint32_t frame = 1300;
  age = nextEvictionAge(age, kFull + 1, kFull, frame++, kWindow);
  EXPECT_EQ(age, 650u) << "the first full frame: what the newer half of the run did not update";
  age = nextEvictionAge(age, kFull + 1, kFull, frame++, kWindow);
  EXPECT_EQ(age, 325u);
  age = nextEvictionAge(age, kFull + 1, kFull, frame++, kWindow);
  EXPECT_EQ(age, kWindow) << "never below the time window: active surfels are not evicted";
  age = nextEvictionAge(age, kFull + 1, kFull, frame++, kWindow);
  EXPECT_EQ(age, kWindow);
}

TEST(MapFullPolicy, AYoungFullMapEvictsEveryInactiveSurfel) {
  // A map that fills within its first frames (tiny capacity) has nothing older than the window.
  EXPECT_EQ(nextEvictionAge(kNoAgeEviction, kFull + 1, kFull, 120, kWindow), kWindow);
}

}  // namespace
}  // namespace vifusion::map
