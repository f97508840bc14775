#include "vifusion/tracking/rotation_term.hpp"

#include "vifusion/shaders/spirv.hpp"

namespace vifusion::tracking {

RotationTerm::RotationTerm(gpu::GpuContext& context, gpu::CapacityPlan& plan, int levels,
                           const PhotometricOptions& options, const LevelReductionOptions& reduction)
    : options_((options.validate(), options)),
      reduction_(context, plan, levels,
                 {"rotation_reduce", shaders::rotation_reduce_subgroup, shaders::rotation_reduce_shared, 3,
                  sizeof(RotationParams)},
                 reduction) {}

void RotationTerm::build(const gpu::MemoryArena& arena, std::span<const RotationInputs> inputs) {
  std::vector<std::vector<gpu::BufferId>> buffers;
  for (const RotationInputs& in : inputs)
    buffers.push_back({in.current_intensity, in.previous_intensity, in.previous_gradients});
  reduction_.build(arena, buffers);
}

void RotationTerm::setRotation(int level, const Eigen::Quaterniond& q_prev_cur, const PinholeCamera& camera) const {
  const RotationParams params = RotationParams::make(q_prev_cur, camera, options_);
  reduction_.writeParams(level, &params);
}

}  // namespace vifusion::tracking
