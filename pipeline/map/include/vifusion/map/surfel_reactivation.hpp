#pragma once
// Reactivation of the inactive surfels a local loop closure brings back into view: every surfel that won a
// pixel of the INACTIVE model's prediction gets last-update frame = the current frame (shaders/map_reactivate.comp),
// so it is active from then on (tracked against, fused into) and the revisited surfaces are not mapped again
// beside it. Run after the closure's deformation and a fresh inactive prediction at the corrected pose, on the
// array that prediction rendered (MapBuffers::current() after Slam's frame). Not per frame: once per closure.
//
// The marked surfels of the inactive prefix then move into the active range (shaders/map_reactivate_move.comp,
// planned on the host from the prediction's ids: planReactivationMoves), and the prefix shrinks by their
// number, so a reactivation costs what the view holds: the next frame's passes visit the active range and the
// reactivated surfels, not the whole map.

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "vifusion/core/image.hpp"
#include "vifusion/gpu/capacity_plan.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/gpu/gpu_context.hpp"
#include "vifusion/gpu/memory_arena.hpp"
#include "vifusion/map/map_buffers.hpp"
#include "vifusion/map/model_prediction.hpp"
#include "vifusion/map/surfel.hpp"

namespace vifusion::map {

class SurfelReactivation {
 public:
  /// Declares the parameter buffer; reads `inactive`'s level-0 splat ids. `map` and `inactive` must outlive this.
  SurfelReactivation(gpu::GpuContext& context, gpu::CapacityPlan& plan, const MapBuffers& map,
                     const ModelPrediction& inactive);
  ~SurfelReactivation();
  SurfelReactivation(const SurfelReactivation&) = delete;
  SurfelReactivation& operator=(const SurfelReactivation&) = delete;

  /// Creates the kernel, one binding set and one recorded sequence per surfel-array parity.
  void build(const gpu::MemoryArena& arena);
  /// Marks the surfels of the last inactive prediction as updated in `frame`, in the current array, moves those
  /// of the inactive prefix into the active range and shrinks the prefix (MapState::active_begin), and waits.
  /// Returns the number of surfels moved out of the prefix.
  std::uint32_t apply(std::uint32_t frame);

 private:
  struct Kernels;

  gpu::GpuContext& context_;
  const MapBuffers& map_;
  gpu::BufferId ids_;
  std::uint32_t pixels_ = 0;
  gpu::BufferId params_;
  gpu::BufferId ids_readback_;               ///< the prediction's ids, for the host's plan
  gpu::BufferId move_plan_;                  ///< the plan: count, then ReactivationMove[pixels]
  std::vector<std::uint32_t> marked_slots_;  ///< the plan's scratch, one per pixel (reserved at start-up)
  const gpu::MemoryArena* arena_ = nullptr;
  std::unique_ptr<Kernels> kernels_;
};

/// CPU reference of map_reactivate.comp: surfels[id].colour_times.z = frame for every id < surfels.size() in `ids`.
void reactivateSurfelsCpu(std::span<Surfel> surfels, ImageView<const std::uint32_t> ids, std::uint32_t frame);

/// One swap of map_reactivate_move.comp (std430 uvec2).
struct ReactivationMove {
  std::uint32_t marked_slot = 0;    ///< a marked surfel below the shrunk prefix's end
  std::uint32_t unmarked_slot = 0;  ///< an unmarked one in [shrunk end, active_begin)
};
static_assert(sizeof(ReactivationMove) == 8);

struct ReactivationPlan {
  std::uint32_t active_begin = 0;  ///< the shrunk prefix's end: active_begin − (distinct marked slots in the prefix)
  std::uint32_t moves = 0;         ///< swaps written
};

/// Plans the swaps that take every slot of `ids` below `active_begin` into [active_begin − r, active_begin), r the
/// number of distinct such slots; ids at or above `active_begin` (kNoSurfel included) are not in the prefix and
/// need no move. `scratch` and `moves` must hold ids.size() entries (no allocation). Deterministic: slots ascend.
ReactivationPlan planReactivationMoves(std::span<const std::uint32_t> ids, std::uint32_t active_begin,
                                       std::span<std::uint32_t> scratch, std::span<ReactivationMove> moves);

/// CPU reference of map_reactivate_move.comp: swaps each pair in `current` and copies the unmarked surfel into
/// `other` at its new prefix slot.
void applyReactivationMovesCpu(std::span<Surfel> current, std::span<Surfel> other,
                               std::span<const ReactivationMove> moves);

}  // namespace vifusion::map
