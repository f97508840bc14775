#pragma once
// The fixed-capacity GPU storage every map kernel shares (fusion, cleanup/compaction, prediction),
// declared once in the capacity plan:
//   surfels[0], surfels[1]  Surfel[capacity] each, device-local. Ping-pong: kernels read and write
//                           the "current" array; compaction copies current → other and the owner
//                           then calls flip(). Only entries [0, surfel_count) are meaningful.
//   state                   one MapState (std430, 16 bytes), host-visible: the host reads the
//                           count after a frame and resets it at start-up; kernels keep it.
//                           Layout of the live surfels [0, surfel_count) in the current array:
//                             [0, active_begin)             inactive (loop-closure memory), identical
//                                                           in both arrays, skipped per frame
//                             [active_begin, surfel_count)  the active surfels and those that turned
//                                                           inactive since the last maintenance
//                           so a per-frame pass costs what the view holds, not what the map holds.
//   index_depth, index_id   one uint per level-0 pixel: the index map of the active surfels
//                           (written by map_index, read by association and cleanup).
// Binding sets are written once, so a kernel that touches the surfels needs one binding set per
// parity, and a command buffer bakes the parity it was recorded with: record one sequence per
// parity (or re-record after flip()) and submit the one matching current().

#include <cstdint>

#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/gpu/capacity_plan.hpp"
#include "vifusion/gpu/memory_arena.hpp"
#include "vifusion/map/surfel.hpp"

namespace vifusion::map {

/// std430 mirror of MapState in shaders/include/map/map_state.glsl.
struct MapState {
  std::uint32_t surfel_count = 0;    ///< surfels in the current array, ≤ capacity
  std::uint32_t overflow_count = 0;  ///< new surfels dropped since start-up because the map was full
  std::uint32_t frame = 0;           ///< frame last fused (written by map_insert)
  /// Surfels [0, active_begin) are inactive and skipped by every per-frame pass; 0 = the next frame
  /// visits the whole map (map_maintenance.hpp).
  std::uint32_t active_begin = 0;
};
static_assert(sizeof(MapState) == 16);

class MapBuffers {
 public:
  /// Declares the buffers for `options.capacity` surfels and an index map of camera's size (level 0).
  /// Throws vifusion::Error when the options are invalid.
  MapBuffers(gpu::CapacityPlan& plan, const MapOptions& options, const PinholeCamera& camera);

  const MapOptions& options() const { return options_; }
  std::uint32_t capacity() const { return options_.capacity; }
  int width() const { return width_; }    ///< index-map width [px]
  int height() const { return height_; }  ///< index-map height [px]

  /// Surfel array `parity` (0 or 1).
  gpu::BufferId surfels(int parity) const { return surfels_[parity & 1]; }
  /// Which surfel array holds the map now (0 or 1); starts at 0.
  int current() const { return current_; }
  gpu::BufferId currentSurfels() const { return surfels_[current_]; }
  gpu::BufferId otherSurfels() const { return surfels_[current_ ^ 1]; }
  /// Swaps current and other, after compaction has written the map into the other array.
  void flip() { current_ ^= 1; }

  gpu::BufferId state() const { return state_; }
  gpu::BufferId indexDepth() const { return index_depth_; }  ///< uint: floatBitsToUint(z_C [m]) of the nearest surfel
  gpu::BufferId indexId() const { return index_id_; }        ///< uint: surfel index + 1, 0 = none

  /// Reads the state (host-visible; call after the frame's submission completed).
  MapState readState(const gpu::MemoryArena& arena) const;
  /// Empties the map: count, overflow and frame to 0 (start-up, or between independent runs).
  void reset(const gpu::MemoryArena& arena);
  /// After MapImport wrote `surfel_count` surfels into the current array: the map holds them, last fused at
  /// `frame`, nothing overflowed, and the next frame visits the whole map. Host write, as reset().
  void setLoaded(const gpu::MemoryArena& arena, std::uint32_t surfel_count, std::uint32_t frame) const;
  /// Makes the next frame's passes visit the whole map (active_begin = 0) and its maintenance
  /// partition it again: after the prefix changed in one array only (a deformation) or when the
  /// inactive ones must be visited (eviction from a full map). Host write: call only while no
  /// submission is in flight. Const like the kernels' own writes: it changes the map's device state only.
  void visitWholeMapNextFrame(const gpu::MemoryArena& arena) const;
  /// Ends the inactive prefix at `active_begin` (≤ the current one) after SurfelReactivation moved the surfels
  /// above it into the active range. Host write, like visitWholeMapNextFrame.
  void shrinkInactivePrefix(const gpu::MemoryArena& arena, std::uint32_t active_begin) const;

 private:
  MapOptions options_;
  int width_ = 0;
  int height_ = 0;
  gpu::BufferId surfels_[2];
  gpu::BufferId state_;
  gpu::BufferId index_depth_;
  gpu::BufferId index_id_;
  int current_ = 0;
};

}  // namespace vifusion::map
