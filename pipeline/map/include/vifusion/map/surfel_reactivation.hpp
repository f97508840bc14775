#pragma once
// Reactivation of the inactive surfels a local loop closure brings back into view (shaders/map_reactivate.comp):
// every surfel that won a pixel of the INACTIVE model's prediction gets last-update frame = the current frame,
// so it is active from then on (tracked against, fused into) and the revisited surfaces are not mapped again
// beside it. Run after the closure's deformation and a fresh inactive prediction at the corrected pose, on the
// array that prediction rendered (MapBuffers::current() after Slam's frame). Not per frame: once per closure.

#include <cstdint>
#include <memory>
#include <span>

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
  /// Marks the surfels of the last inactive prediction as updated in `frame`, in the current array, and waits;
  /// the next frame visits the whole map (MapBuffers::visitWholeMapNextFrame), so they rejoin the active range.
  void apply(std::uint32_t frame);

 private:
  struct Kernels;

  gpu::GpuContext& context_;
  const MapBuffers& map_;
  gpu::BufferId ids_;
  std::uint32_t pixels_ = 0;
  gpu::BufferId params_;
  const gpu::MemoryArena* arena_ = nullptr;
  std::unique_ptr<Kernels> kernels_;
};

/// CPU reference of map_reactivate.comp: surfels[id].colour_times.z = frame for every id < surfels.size() in `ids`.
void reactivateSurfelsCpu(std::span<Surfel> surfels, ImageView<const std::uint32_t> ids, std::uint32_t frame);

}  // namespace vifusion::map
