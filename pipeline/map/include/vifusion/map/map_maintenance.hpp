#pragma once
// Map maintenance on the GPU (DESIGN.md §4.4): cleanup decides which surfels stay, stream
// compaction moves them into the other ping-pong array. Recorded once per surfel-array parity;
// afterwards the map lives in the other array (MapBuffers::flip()) and the map state holds the
// new surfel_count.
//
//   map_cleanup          one keep flag per surfel (rules in shaders/map_cleanup.comp), counters
//   map_compact_scan     exclusive scan of the flags in 1024-element tiles, then of the tile
//                        totals, … until one tile (include/map/compact.glsl)
//   map_compact_add      tile offsets made global, top level down
//   map_compact_scatter  kept surfels to their offsets in the other array (stable order)
//   map_compact_finish   surfel_count ← total
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
  float free_space_margin_m = 0.01f;           ///< ElasticFusion's 1 cm
  float facing_min_abs_nz = 0.85f;             ///< ElasticFusion's facing test on |n_C.z|
  std::uint32_t free_space_min_neighbours = 5; ///< of the 3×3 index-map window ("> 4")
  float full_fraction = 0.95f;                 ///< the map is full above this fraction of capacity
  /// When full, inactive surfels below this confidence are evicted; the default is the default
  /// stability threshold, so only inactive surfels that never became stable go.
  float eviction_confidence = 10.0f;
  std::uint32_t workgroups = 256;              ///< workgroups of the grid-stride passes
  std::uint32_t workgroup_size = 128;          ///< invocations per workgroup of those passes

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
  /// it, then writes the parameters for the next submission (host, no allocation).
  void setView(const SE3d& T_C_W, std::uint32_t frame);

  /// Cleanup then compaction from array `parity` into array 1 − parity, ending with a barrier that
  /// makes the new map, count and counters visible to later kernels and the host.
  void record(gpu::CommandRecorder& recorder, int parity) const;
  /// Zeroes the counters and writes the keep flags (tests record the steps apart).
  void recordCleanup(gpu::CommandRecorder& recorder, int parity) const;
  /// Scans the keep flags, scatters array `parity` into 1 − parity and sets surfel_count.
  void recordCompaction(gpu::CommandRecorder& recorder, int parity) const;

  /// The map is full above this many surfels (full_fraction·capacity).
  std::uint32_t fullCount() const;

  /// Counters of the last completed submission.
  MaintenanceStats stats() const;
  gpu::BufferId keepFlags() const { return keep_; }       ///< uint per surfel, 1 keep / 0 remove
  gpu::BufferId offsets() const { return offsets_[0]; }   ///< tile-local exclusive offsets (level 0)
  int scanLevels() const { return static_cast<int>(offsets_.size()); }  ///< levels incl. the flags' level 0

 private:
  struct Kernels;

  gpu::GpuContext& context_;
  MaintenanceOptions options_;
  MapOptions map_options_;
  PinholeCamera camera_;
  gpu::BufferId surfels_[2];
  gpu::BufferId state_;
  gpu::BufferId index_depth_;
  gpu::BufferId index_id_;
  gpu::BufferId params_;
  gpu::BufferId stats_;
  gpu::BufferId keep_;
  std::vector<gpu::BufferId> offsets_;    ///< [0]: level 0 (per surfel); [k]: scanned level k
  std::vector<gpu::BufferId> tile_sums_;  ///< [k]: input of level k+1; the last one is the total
  std::vector<std::uint32_t> level_sizes_;  ///< largest element count of each level
  const gpu::MemoryArena* arena_ = nullptr;
  std::unique_ptr<Kernels> kernels_;
  std::uint32_t eviction_age_frames_ = kNoAgeEviction;  ///< the map-full policy's state
};

}  // namespace vifusion::map
