#pragma once
// Reactivation of the inactive surfels the camera sees again: every surfel the inactive model's prediction renders
// whose centre lies on that prediction's surface within the fusion association's gates gets last-update frame =
// the prediction's frame (shaders/map_reactivate.comp), so it is active from then on (tracked against, fused into)
// and the revisited surfaces are not mapped again beside it. Run after a fresh inactive prediction at the pose the
// surfels should come back at (a closure's corrected pose; a tracked frame in a loaded map), on the array that
// prediction rendered (MapBuffers::current() after Slam's frame).
//
// The marked surfels of the inactive prefix then move into the active range (shaders/map_reactivate_move.comp,
// planned on the host from the kernel's list of marked indices: planReactivationMoves), and the prefix shrinks by
// their number, so a reactivation costs what the view holds: the next frame's passes visit the active range and
// the reactivated surfels, not the whole map.

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "vifusion/core/image.hpp"
#include "vifusion/gpu/capacity_plan.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/gpu/gpu_context.hpp"
#include "vifusion/gpu/memory_arena.hpp"
#include "vifusion/map/fusion_params.hpp"
#include "vifusion/map/map_buffers.hpp"
#include "vifusion/map/model_prediction.hpp"
#include "vifusion/map/prediction_cpu.hpp"
#include "vifusion/map/surfel.hpp"

namespace vifusion::map {

/// std430 mirror of map_reactivate.comp's ReactivateGates: the fusion association's gates (FusionOptions), for a
/// surfel centre against the predicted surface at its pixel, and the most surfels one reactivation marks.
struct ReactivateGates {
  float max_depth_diff2_m2 = 0;  ///< τ², τ = FusionOptions::max_depth_diff_m [m²]
  float min_normal_cos = 0;      ///< cos(FusionOptions::max_normal_angle_rad)
  float grazing_normal_z = 0;    ///< FusionOptions::grazing_normal_z
  std::uint32_t capacity = 0;    ///< most surfels one reactivation marks

  static ReactivateGates of(const FusionOptions& fusion, std::uint32_t capacity);
};
static_assert(sizeof(ReactivateGates) == 16);

/// Surfels one reactivation marks at most, per level-0 pixel. Surfels are made about one per pixel where a surface
/// was first mapped, so 2 covers a surface seen again from up to √2 times as far; the rest are taken by the next
/// reactivation that sees them (the following frame, in a loaded map).
inline constexpr std::uint32_t kReactivatedPerPixel = 2;

class SurfelReactivation {
 public:
  /// Declares the gate, list and plan buffers; reads `inactive`'s parameters and level-0 vertex and normal maps.
  /// `fusion`: the association gates a surfel must pass against the predicted surface. `map` and `inactive` must
  /// outlive this.
  SurfelReactivation(gpu::GpuContext& context, gpu::CapacityPlan& plan, const MapBuffers& map,
                     const ModelPrediction& inactive, const FusionOptions& fusion);
  ~SurfelReactivation();
  SurfelReactivation(const SurfelReactivation&) = delete;
  SurfelReactivation& operator=(const SurfelReactivation&) = delete;

  /// Creates the kernel, one binding set and one recorded sequence per surfel-array parity.
  void build(const gpu::MemoryArena& arena);
  /// Marks the surfels on the last inactive prediction's surface as updated in its frame, in the current array,
  /// moves those of the inactive prefix into the active range and shrinks the prefix (MapState::active_begin), and
  /// waits. Returns the number of surfels moved out of the prefix.
  std::uint32_t apply();
  /// Surfels the last apply() found on the surface, including any past the capacity it left for later.
  std::uint32_t lastFound() const { return last_found_; }
  std::uint32_t capacity() const { return gates_.capacity; }

 private:
  struct Kernels;

  gpu::GpuContext& context_;
  const MapBuffers& map_;
  const ModelPrediction& inactive_;
  ReactivateGates gates_;
  std::uint32_t last_found_ = 0;
  gpu::BufferId gates_buffer_;
  gpu::BufferId marked_count_;               ///< the kernel's append counter (host-visible)
  gpu::BufferId marked_;                     ///< the marked surfels' indices, capacity of them (host-visible)
  gpu::BufferId move_plan_;                  ///< the plan: count, then ReactivationMove[capacity]
  std::vector<std::uint32_t> marked_slots_;  ///< the plan's scratch, capacity of them (reserved at start-up)
  const gpu::MemoryArena* arena_ = nullptr;
  std::unique_ptr<Kernels> kernels_;
};

/// CPU reference of map_reactivate.comp: marks (colour_times.z = params.view.frame) every surfel `params` renders whose
/// centre lies on the predicted surface (`vertices`, `normals`: the prediction's level-0 maps) within `gates`, at
/// most gates.capacity of them in index order, and returns their indices, ascending. (The GPU's list holds the same
/// indices in any order; past the capacity, which ones it keeps depends on the execution order.)
std::vector<std::uint32_t> reactivateInViewCpu(std::span<Surfel> surfels, const PredictionParams& params,
                                               ImageView<const Eigen::Vector4f> vertices,
                                               ImageView<const Eigen::Vector4f> normals, const ReactivateGates& gates);

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
