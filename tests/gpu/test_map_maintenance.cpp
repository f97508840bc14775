// Map maintenance on the GPU against its CPU references: the compaction of keep and retire flags (a stable
// partition of the visited range behind the inactive prefix, exact at 2 M surfels, the prefix the same in both
// arrays afterwards) and the cleanup rules (retirement, unstable, free-space and full-map eviction of inactive
// surfels), exact for flags, counts and compacted arrays, over the whole map and over an active range only.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <random>
#include <utility>
#include <vector>

#include "gpu_test_environment.hpp"
#include "map_test_rig.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/map/map_buffers.hpp"
#include "vifusion/map/map_maintenance.hpp"
#include "vifusion/map/model_prediction.hpp"
#include "vifusion/preprocess/cpu_reference.hpp"
#include "vifusion/test/expect_error.hpp"
#include "vifusion/test/seven_scenes_frame.hpp"

namespace vifusion {
namespace {

/// Surfel i sits at x = i, so any reordering or loss shows in the compacted array.
std::vector<Surfel> numberedSurfels(std::size_t count) {
  std::vector<Surfel> surfels(count);
  for (std::size_t i = 0; i < count; ++i) {
    surfels[i].position_confidence = Eigen::Vector4f(static_cast<float>(i), 1.0f, 2.0f, 3.0f);
    surfels[i].colour_times.w() = std::bit_cast<float>(static_cast<std::uint32_t>(i));  // exact beyond 2^24
  }
  return surfels;
}

bool sameSurfel(const Surfel& a, const Surfel& b) { return std::memcmp(&a, &b, sizeof(Surfel)) == 0; }

TEST_F(GpuTest, CompactionOfRandomFlagsAt2MSurfelsIsAStablePartition) {
  constexpr std::uint32_t kCapacity = 2'000'000;
  MapRig rig(context(), kCapacity, PinholeCamera::create(64, 48, 50, 50, 32, 24));
  EXPECT_EQ(rig.maintenance().scanLevels(), 3);  // 2 M flags → 1954 tile sums → 2 → total
  std::mt19937 random(7);
  struct Case {
    std::uint32_t count, active_begin;
    double keep, retire;  // probabilities per visited surfel; the rest is removed
  };
  // Full map visited whole, half kept, a quarter retired; a partial last tile with few survivors behind a
  // long prefix; a visited range of one surfel; an empty map.
  for (const Case c : {Case{kCapacity, 0, 0.5, 0.25},
                       {1'234'567u, 1'000'003u, 0.01, 0.02},
                       {77u, 76u, 0.0, 1.0},
                       {0u, 0u, 0.5, 0.25}}) {
    SCOPED_TRACE("count " + std::to_string(c.count) + ", active_begin " + std::to_string(c.active_begin));
    const std::vector<Surfel> surfels = numberedSurfels(c.count);
    rig.writeMap(surfels, c.active_begin);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::span<std::uint32_t> keep = rig.keepUpload().first(c.count - c.active_begin);
    std::span<std::uint32_t> retire = rig.retireUpload().first(c.count - c.active_begin);
    for (std::uint32_t k = 0; k < keep.size(); ++k) {
      const double u = unit(random);
      keep[k] = u < c.keep ? 1u : 0u;
      retire[k] = u >= c.keep && u < c.keep + c.retire ? 1u : 0u;
    }
    rig.compactUploadedFlags();

    std::vector<Surfel> expected(c.count);
    const map::MapExtent extent = map::compactCpu(surfels, c.active_begin, keep, retire, expected);
    ASSERT_EQ(rig.extent(), extent);
    EXPECT_EQ(rig.maintenance().stats().kept, extent.surfel_count);
    std::size_t mismatches = 0, prefix_mismatches = 0;
    for (std::uint32_t i = 0; i < extent.surfel_count; ++i) {
      mismatches += sameSurfel(rig.compacted()[i], expected[i]) ? 0 : 1;
    }
    // The other array (compacted from) ends with the same inactive prefix.
    for (std::uint32_t i = 0; i < extent.active_begin; ++i) {
      prefix_mismatches += sameSurfel(rig.previous()[i], expected[i]) ? 0 : 1;
    }
    EXPECT_EQ(mismatches, 0u);
    EXPECT_EQ(prefix_mismatches, 0u);
  }
}

/// Level-0 index map as fusion's index kernel defines it: per pixel the nearest centre of an
/// active surfel (camera depth bits, index + 1). Exact ties go to the lower index (map_index picks
/// the higher; either serves the cleanup rules, which only read the neighbours' depth and state).
void nearestCentreIndexMap(std::span<const Surfel> surfels, const map::MapView& view, std::uint32_t time_window,
                           Image<std::uint32_t>& depth_bits, Image<std::uint32_t>& ids) {
  depth_bits.resize(view.width, view.height, 0xffffffffu);
  ids.resize(view.width, view.height, 0u);
  for (std::size_t i = 0; i < surfels.size(); ++i) {
    if (map::framesSinceCpu(view, surfels[i].colour_times.z()) > time_window) continue;
    const Eigen::Vector3f p_C = map::transformPointCpu(view, surfels[i].position_confidence.head<3>());
    if (p_C.z() <= 0.0f) continue;
    const Eigen::Vector2f uv = map::projectPointCpu(view, p_C);
    const int x = static_cast<int>(std::floor(uv.x() + 0.5f));
    const int y = static_cast<int>(std::floor(uv.y() + 0.5f));
    if (!depth_bits.view().contains(x, y)) continue;
    const std::uint32_t bits = std::bit_cast<std::uint32_t>(p_C.z());
    if (bits < depth_bits(x, y)) {
      depth_bits(x, y) = bits;
      ids(x, y) = static_cast<std::uint32_t>(i + 1);
    }
  }
}

enum class Kind { Wall, Floater, OldUnstable, Inactive, InactiveUnstable, InactiveOld };

// Inactive surfels stay unless the map is full; then the never-stable ones go and, by the map-full
// policy's age (half the run on the first full frame: 500 of kFrame = 1000), the old stable ones.
TEST_F(GpuTest, CleanupMatchesItsCpuReferenceAndEvictsInactiveSurfelsOnlyWhenFull) {
  const test::SevenScenesFrame frame = test::loadSevenScenesFrame(150);
  const std::vector<Surfel> wall = surfelsFromFrame(frame, frameGeometry(frame), 20.0f);
  const Eigen::Vector3f camera_W = frame.T_W_C.translation().cast<float>();
  // Every 20th wall surfel gets one of five companions 20 cm in front of it.
  std::vector<Surfel> surfels = wall;
  std::vector<Kind> kinds(wall.size(), Kind::Wall);
  for (std::size_t i = 0; i < wall.size(); i += 20) {
    const auto kind = static_cast<Kind>(1 + (i / 20) % 5);
    Surfel s = movedToward(wall[i], camera_W, 0.20f);
    if (kind == Kind::Floater) s.colour_times.z() = static_cast<float>(kFrame - 5);
    if (kind == Kind::OldUnstable) {
      s.position_confidence.w() = 2.0f;
      s.colour_times.z() = static_cast<float>(kFrame - 30);
    }
    if (kind == Kind::Inactive || kind == Kind::InactiveUnstable) s.colour_times.z() = static_cast<float>(kFrame - 250);
    if (kind == Kind::InactiveUnstable) s.position_confidence.w() = 1.0f;
    if (kind == Kind::InactiveOld) s.colour_times.z() = static_cast<float>(kFrame - 600);
    surfels.push_back(s);
    kinds.push_back(kind);
  }
  const SE3d T_C_W = frame.T_W_C.inverse();

  // A roomy map visited whole; the same with the first half of the wall as the inactive prefix, which the
  // cleanup skips (no flags, no counts); then one over 95 % full with the same prefix, which setView visits
  // whole (active_begin back to 0) so that the inactive unstable and old surfels are evicted.
  struct Case {
    std::uint32_t capacity, active_begin;
  };
  const auto half = static_cast<std::uint32_t>(wall.size() / 2);
  const auto full_capacity = static_cast<std::uint32_t>(surfels.size() * 1.02);
  for (const Case c : {Case{400'000u, 0u}, {400'000u, half}, {full_capacity, half}}) {
    SCOPED_TRACE("capacity " + std::to_string(c.capacity) + ", active_begin " + std::to_string(c.active_begin));
    MapRig rig(context(), c.capacity, frame.camera);
    const map::MapView view = rig.maintenance().makeParams(T_C_W, kFrame).view;
    Image<std::uint32_t> index_depth, index_id;
    nearestCentreIndexMap(surfels, view, map::MapOptions{}.time_window_frames, index_depth, index_id);
    rig.writeIndexMap(index_depth.view(), index_id.view());
    rig.writeMap(surfels, c.active_begin);
    rig.cleanup(T_C_W);  // the map-full policy's first frame at this count
    const map::CleanupParams params = rig.maintenance().makeParams(T_C_W, kFrame);
    const bool full = surfels.size() > params.full_count;
    EXPECT_EQ(params.eviction_age_frames, full ? kFrame / 2 : map::kNoAgeEviction);
    const std::uint32_t begin = full ? 0u : c.active_begin;
    EXPECT_EQ(rig.extent().active_begin, begin);

    const std::size_t visited = surfels.size() - begin;
    std::vector<std::uint32_t> keep(visited), retire(visited);
    map::MaintenanceStats expected;
    map::cleanupCpu(surfels, begin, params, index_depth.view(), index_id.view(), keep, retire, expected);
    EXPECT_TRUE(std::equal(keep.begin(), keep.end(), rig.keep().begin()));
    EXPECT_TRUE(std::equal(retire.begin(), retire.end(), rig.retire().begin()));
    EXPECT_EQ(rig.maintenance().stats(), expected);

    std::size_t removed[6] = {}, retired[6] = {}, total[6] = {}, facing_floaters = 0;
    for (std::size_t i = begin; i < surfels.size(); ++i) {
      const int kind = int(kinds[i]);
      ++total[kind];
      removed[kind] += keep[i - begin] == 0u && retire[i - begin] == 0u ? 1 : 0;
      retired[kind] += retire[i - begin];
      const Eigen::Vector3f n_C = map::rotateVectorCpu(params.view, surfels[i].normal_radius.head<3>());
      facing_floaters += kinds[i] == Kind::Floater && std::abs(n_C.z()) > params.facing_min_abs_nz ? 1 : 0;
    }
    EXPECT_EQ(removed[int(Kind::Inactive)], 0u);
    EXPECT_EQ(retired[int(Kind::Inactive)], total[int(Kind::Inactive)]);
    EXPECT_EQ(removed[int(Kind::InactiveUnstable)], full ? total[int(Kind::InactiveUnstable)] : 0u);
    EXPECT_EQ(removed[int(Kind::InactiveOld)], full ? total[int(Kind::InactiveOld)] : 0u);
    EXPECT_EQ(expected.evicted_when_full,
              full ? total[int(Kind::InactiveUnstable)] + total[int(Kind::InactiveOld)] : 0u);
    EXPECT_EQ(expected.retired,
              retired[int(Kind::Inactive)] + retired[int(Kind::InactiveUnstable)] + retired[int(Kind::InactiveOld)]);
    EXPECT_EQ(retired[int(Kind::Wall)] + retired[int(Kind::Floater)] + retired[int(Kind::OldUnstable)], 0u);
    EXPECT_EQ(removed[int(Kind::OldUnstable)], total[int(Kind::OldUnstable)]);
    // Floaters are only tested when they face the camera; nearly all of those are seen through.
    EXPECT_LE(removed[int(Kind::Floater)], facing_floaters);
    EXPECT_GE(removed[int(Kind::Floater)], facing_floaters * 9 / 10);
    // Wall surfels go only at depth edges, where most of a 3×3 window lies on a farther surface.
    EXPECT_LE(removed[int(Kind::Wall)], total[int(Kind::Wall)] / 200);
    std::cout << "full " << full << ": removed floaters " << removed[int(Kind::Floater)] << " (facing "
              << facing_floaters << " of " << total[int(Kind::Floater)] << "), wall " << removed[int(Kind::Wall)] << "/"
              << total[int(Kind::Wall)] << ", retired " << expected.retired << "\n";

    // The whole maintenance step: cleanup then compaction into array 1. A second frame at this count:
    // a full map halves the eviction age (250 frames), which still spares Kind::Inactive (age 250).
    rig.maintain(T_C_W);
    const map::CleanupParams second = rig.maintenance().makeParams(T_C_W, kFrame);
    EXPECT_EQ(second.eviction_age_frames, full ? kFrame / 4 : map::kNoAgeEviction);
    map::MaintenanceStats second_stats;
    map::cleanupCpu(surfels, begin, second, index_depth.view(), index_id.view(), keep, retire, second_stats);
    EXPECT_EQ(second_stats, expected);
    std::vector<Surfel> compacted(surfels.size());
    const map::MapExtent extent = map::compactCpu(surfels, begin, keep, retire, compacted);
    ASSERT_EQ(rig.extent(), extent);
    EXPECT_EQ(extent.active_begin, begin + expected.retired);
    EXPECT_EQ(rig.maintenance().stats().kept, extent.surfel_count);
    std::size_t mismatches = 0;
    for (std::uint32_t i = 0; i < extent.surfel_count; ++i) {
      mismatches += sameSurfel(rig.compacted()[i], compacted[i]) ? 0 : 1;
    }
    EXPECT_EQ(mismatches, 0u);
  }
}

}  // namespace
}  // namespace vifusion
