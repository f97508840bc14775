#pragma once
// Map maintenance on the GPU (DESIGN.md §4.4): cleanup decides which surfels stay, stream
// compaction moves them into the other ping-pong array. Recorded once per surfel-array parity;
// afterwards the map lives in the other array (MapBuffers::flip()) and the map state holds the
// new surfel_count and active_begin.
//
// Only the visited range [active_begin, surfel_count) is cleaned and compacted (map_buffers.hpp):
// its surfels that turned inactive are retired to the end of the inactive prefix, which is the
// same in both arrays and is never walked per frame, so a frame's maintenance (and index, fusion
// and active prediction) costs what the active map holds, not the whole map. The whole map is
// visited when active_begin is 0: at start-up, after MapBuffers::visitWholeMapNextFrame (after a loop
// closure deformed the map) and on every frame the map is over its full mark (setView), whose eviction
// needs the inactive surfels. Reactivated surfels leave the prefix without that (surfel_reactivation.hpp).
//
//   map_cleanup          keep and retire flags per visited surfel (rules in shaders/map_cleanup.comp)
//   map_compact_scan     exclusive scan of each chain of flags in 1024-element tiles, then of the
//                        tile totals, … until one tile (include/map/compact.glsl)
//   map_compact_add      tile offsets made global, top level down
//   map_compact_scatter  retired surfels to the prefix's end, kept ones after them, in the other
//                        array (stable order)
//   map_compact_prefix   the retired surfels copied back into the current array too
//   map_compact_finish   active_begin += retired, surfel_count ← active_begin + kept
//
// Map-full policy: when surfel_count > full_fraction·capacity, cleanup evicts (and counts) the
// inactive surfels that never became stable (confidence below eviction_confidence) and those not
// updated for longer than an age that halves while the map stays full (nextEvictionAge): the
// never-confirmed, then the oldest loop-closure memory goes, and the map keeps taking in the view.
// Without it a map full of stable surfels dropped every new surfel: 640×480 sim:living_room_0
// filled 2 M surfels at 44 s (revisited rooms are mapped again while their surfels are inactive),
// the view left the map and tracking ran away (ATE 8.8 mm before, 228 mm over the whole run; with
// the policy: 7.5 mm, nothing lost, 1.7 M surfels at the end).
// Inactive surfels are never removed otherwise.

#include <cstdint>
#include <memory>
#include <vector>

#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/gpu/capacity_plan.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/gpu/compute_kernel.hpp"
#include "vifusion/gpu/gpu_context.hpp"
#include "vifusion/gpu/memory_arena.hpp"
#include "vifusion/map/maintenance_cpu.hpp"
#include "vifusion/map/map_buffers.hpp"

namespace vifusion::map {

/// Elements a workgroup of map_compact_scan scans per tile (4 per invocation × 256 invocations).
inline constexpr std::uint32_t kCompactTileSize = 1024;

struct MaintenanceOptions {
  float free_space_margin_m = 0.01f;            ///< ElasticFusion's 1 cm
  float facing_min_abs_nz = 0.85f;              ///< ElasticFusion's facing test on |n_C.z|
  std::uint32_t free_space_min_neighbours = 5;  ///< of the 3×3 index-map window ("> 4")
  float full_fraction = 0.95f;                  ///< the map is full above this fraction of capacity
  /// When full, inactive surfels below this confidence are evicted; the default is the default
  /// stability threshold, so only inactive surfels that never became stable go.
  float eviction_confidence = 10.0f;
  std::uint32_t workgroups = 256;      ///< workgroups of the grid-stride passes
  std::uint32_t workgroup_size = 128;  ///< invocations per workgroup of those passes

  /// Throws vifusion::Error naming the field that is out of range.
  void validate() const;
};

class MapMaintenance {
 public:
  /// Declares the keep flags, scan levels, parameters and counters for the map's capacity.
  /// `camera`: level-0 intrinsics of the index map. Throws vifusion::Error on bad options.
  MapMaintenance(gpu::GpuContext& context, gpu::CapacityPlan& plan, const MapBuffers& map, const PinholeCamera& camera,
                 const MaintenanceOptions& options = {});
  ~MapMaintenance();

  void build(const gpu::MemoryArena& arena);

  /// The cleanup parameters for the index map rendered at T_C_W in frame `frame`.
  CleanupParams makeParams(const SE3d& T_C_W, std::uint32_t frame) const;
  /// Advances the map-full policy by the map's surfel_count as the last completed submission left
  /// it, then writes the parameters for the next submission (host, no allocation). A map over its
  /// full mark is visited whole in the next submission (active_begin ← 0), so the eviction reaches
  /// the inactive prefix.
  void setView(const SE3d& T_C_W, std::uint32_t frame);

  /// Cleanup then compaction from array `parity` into array 1 − parity, ending with a barrier that
  /// makes the new map, count and counters visible to later kernels and the host.
  void record(gpu::CommandRecorder& recorder, int parity) const;
  /// Zeroes the counters and writes the keep and retire flags (tests record the steps apart).
  void recordCleanup(gpu::CommandRecorder& recorder, int parity) const;
  /// Scans both chains of flags, scatters the visited range of array `parity` into 1 − parity, copies
  /// the retired surfels back into `parity` and sets active_begin and surfel_count.
  void recordCompaction(gpu::CommandRecorder& recorder, int parity) const;

  /// The map is full above this many surfels (full_fraction·capacity).
  std::uint32_t fullCount() const;

  /// Counters of the last completed submission.
  MaintenanceStats stats() const;
  /// uint per visited surfel (at index − active_begin): 1 stays active, 0 not.
  gpu::BufferId keepFlags() const { return keep_.flags; }
  /// uint per visited surfel: 1 moves to the inactive prefix, 0 not.
  gpu::BufferId retireFlags() const { return retire_.flags; }
  gpu::BufferId offsets() const {
    return keep_.offsets[0];
  }  ///< tile-local exclusive offsets of the keep flags (level 0)
  int scanLevels() const { return static_cast<int>(keep_.offsets.size()); }  ///< levels incl. the flags' level 0

 private:
  struct Kernels;
  /// One chain of flags and its scan levels.
  struct ScanChain {
    gpu::BufferId flags;
    std::vector<gpu::BufferId> offsets;    ///< [0]: level 0 (per visited surfel); [k]: scanned level k
    std::vector<gpu::BufferId> tile_sums;  ///< [k]: input of level k+1; the last one is the total
  };
  ScanChain declareChain(gpu::CapacityPlan& plan, const char* name);

  gpu::GpuContext& context_;
  MaintenanceOptions options_;
  MapOptions map_options_;
  PinholeCamera camera_;
  gpu::BufferId surfels_[2];
  gpu::BufferId state_;
  gpu::BufferId index_depth_;
  gpu::BufferId index_id_;
  const MapBuffers& map_;
  gpu::BufferId params_;
  gpu::BufferId stats_;
  ScanChain keep_;
  ScanChain retire_;
  std::vector<std::uint32_t> level_sizes_;  ///< largest element count of each level (both chains)
  const gpu::MemoryArena* arena_ = nullptr;
  std::unique_ptr<Kernels> kernels_;
  std::uint32_t eviction_age_frames_ = kNoAgeEviction;  ///< the map-full policy's state
};

}  // namespace vifusion::map
