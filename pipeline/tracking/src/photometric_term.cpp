#include "vifusion/tracking/photometric_term.hpp"

#include "vifusion/shaders/spirv.hpp"

namespace vifusion::tracking {

PhotometricTerm::PhotometricTerm(gpu::GpuContext& context, gpu::CapacityPlan& plan, int levels,
                                 const PhotometricOptions& options, const LevelReductionOptions& reduction)
    : options_((options.validate(), options)),
      reduction_(context, plan, levels,
                 {"photometric_reduce", shaders::photometric_reduce_subgroup, shaders::photometric_reduce_shared, 5,
                  sizeof(PhotometricParams)},
                 reduction) {}

void PhotometricTerm::build(const gpu::MemoryArena& arena, std::span<const PhotometricLevelInputs> inputs) {
  std::vector<std::vector<gpu::BufferId>> buffers;
  for (const PhotometricLevelInputs& in : inputs) {
    buffers.push_back({in.current_vertices, in.current_intensity, in.reference_intensity, in.reference_gradients,
                       in.reference_vertices});
  }
  reduction_.build(arena, buffers);
}

void PhotometricTerm::setPose(int level, const SE3d& T_ref_cur, const PinholeCamera& camera,
                              bool use_reference_fill) const {
  const PhotometricParams params = PhotometricParams::make(T_ref_cur, camera, options_, level, use_reference_fill);
  reduction_.writeParams(level, &params);
}

}  // namespace vifusion::tracking
