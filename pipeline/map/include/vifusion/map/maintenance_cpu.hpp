#pragma once
// Map maintenance on the CPU: the references of map_cleanup.comp (same float arithmetic, so keep
// flags agree exactly) and of the prefix-sum compaction (map_compact_*.comp), plus the parameter
// block and counters the kernels share with the host (std430 mirrors of
// shaders/include/map/cleanup.glsl).

#include <cstddef>
#include <cstdint>
#include <span>

#include "vifusion/core/image.hpp"
#include "vifusion/map/prediction_cpu.hpp"
#include "vifusion/map/surfel.hpp"

namespace vifusion::map {

/// CleanupParams in cleanup.glsl; map_cleanup.comp documents each rule.
struct CleanupParams {
  MapView view;                                 ///< pose and frame of the index map
  float confidence_threshold = 0;               ///< stable when confidence ≥ this
  std::uint32_t time_window_frames = 0;         ///< δ_t: active when updated within this many frames
  std::uint32_t unstable_max_age_frames = 0;    ///< unstable surfels not updated for longer are removed
  float max_depth_m = 0;                        ///< free-space test only within this depth [m]
  float free_space_margin_m = 0;                ///< neighbours must lie this far behind [m]
  float facing_min_abs_nz = 0;                  ///< the surfel must face the camera: |n_C.z| > this
  std::uint32_t free_space_min_neighbours = 0;  ///< removed when ≥ this many neighbours agree
  std::uint32_t full_count = 0;                 ///< the map is full when surfel_count > this
  float eviction_confidence = 0;                ///< when full, inactive surfels below this go
  /// When full, inactive surfels not updated for more than this many frames go too (nextEvictionAge).
  std::uint32_t eviction_age_frames = 0;
  std::uint32_t pad[2] = {};
};
static_assert(sizeof(CleanupParams) == 144);
static_assert(offsetof(CleanupParams, confidence_threshold) == 96);
static_assert(offsetof(CleanupParams, full_count) == 124);
static_assert(offsetof(CleanupParams, eviction_confidence) == 128);
static_assert(offsetof(CleanupParams, eviction_age_frames) == 132);

/// eviction_age_frames when nothing is evicted for its age.
inline constexpr std::uint32_t kNoAgeEviction = 0xFFFFFFFFu;

/// The map-full policy's age limit for the next frame. A map that ended the last frame above its
/// full mark (surfel_count > full_count) evicts its inactive surfels oldest first: the first full
/// frame those not updated in the newer half of the run (age > frame / 2), and each further full
/// frame halves the age, down to the time window (every inactive surfel); a map below the mark
/// evicts nothing for age (kNoAgeEviction). Inactive surfels are neither rendered nor fused, so
/// tracking never misses them; what goes is the oldest loop-closure memory.
std::uint32_t nextEvictionAge(std::uint32_t age_frames, std::uint32_t surfel_count, std::uint32_t full_count,
                              std::uint32_t frame, std::uint32_t time_window_frames);

/// Counters of one maintenance pass (VIFUSION_MAINTENANCE_STATS_MEMBERS in cleanup.glsl).
struct MaintenanceStats {
  std::uint32_t kept = 0;                ///< surfels after compaction
  std::uint32_t removed_unstable = 0;    ///< unstable and not updated for too long
  std::uint32_t removed_free_space = 0;  ///< seen through this frame
  std::uint32_t evicted_when_full = 0;   ///< inactive, never stable or old, map over its full mark
  std::uint32_t retired = 0;             ///< turned inactive: moved to the inactive prefix
  bool operator==(const MaintenanceStats&) const = default;
};
static_assert(sizeof(MaintenanceStats) == 20);

/// Keep flags (1 stays active) and retire flags (1 moves to the inactive prefix; both 0: removed) of
/// the visited surfels [active_begin, surfels.size()) of the live map `surfels` (MapState says why the
/// prefix is skipped); `keep` and `retire` have surfels.size() − active_begin entries. index_depth/index_id:
/// the level-0 index map (float bits of camera depth; surfel index + 1, 0 = none). Fills the removal and
/// retirement counters of `stats` (kept is left to compaction).
void cleanupCpu(std::span<const Surfel> surfels, std::uint32_t active_begin, const CleanupParams& params,
                ImageView<const std::uint32_t> index_depth, ImageView<const std::uint32_t> index_id,
                std::span<std::uint32_t> keep, std::span<std::uint32_t> retire, MaintenanceStats& stats);

/// Exclusive prefix sum of `values` into `offsets` (same size); returns the total.
std::uint32_t exclusiveScanCpu(std::span<const std::uint32_t> values, std::span<std::uint32_t> offsets);

/// Where the live surfels lie after a compaction (MapState's fields of the same names).
struct MapExtent {
  std::uint32_t active_begin = 0;
  std::uint32_t surfel_count = 0;
  bool operator==(const MapExtent&) const = default;
};

/// Stable partition of the visited range [active_begin, surfels.size()) by its flags (cleanupCpu's):
/// destination = the prefix [0, active_begin) unchanged, then the retired surfels in order, then the
/// kept ones in order (`destination` has ≥ surfels.size() entries). Returns the new extent.
MapExtent compactCpu(std::span<const Surfel> surfels, std::uint32_t active_begin, std::span<const std::uint32_t> keep,
                     std::span<const std::uint32_t> retire, std::span<Surfel> destination);

}  // namespace vifusion::map
