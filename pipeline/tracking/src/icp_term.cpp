#include "vifusion/tracking/icp_term.hpp"

#include "vifusion/shaders/spirv.hpp"

namespace vifusion::tracking {

IcpTerm::IcpTerm(gpu::GpuContext& context, gpu::CapacityPlan& plan, int levels, const IcpOptions& options,
                 const LevelReductionOptions& reduction, const std::string& name)
    : options_((options.validate(), options)),
      reduction_(context, plan, levels,
                 {name, shaders::icp_reduce_subgroup, shaders::icp_reduce_shared, 4, sizeof(IcpParams)}, reduction) {}

void IcpTerm::build(const gpu::MemoryArena& arena, std::span<const IcpLevelInputs> inputs) {
  std::vector<std::vector<gpu::BufferId>> buffers;
  for (const IcpLevelInputs& in : inputs) {
    buffers.push_back({in.current_vertices, in.current_normals, in.model_vertices, in.model_normals});
  }
  reduction_.build(arena, buffers);
}

void IcpTerm::setPose(int level, const SE3d& T_ref_cur, const PinholeCamera& camera) const {
  const IcpParams params = IcpParams::make(T_ref_cur, camera, options_);
  reduction_.writeParams(level, &params);
}

}  // namespace vifusion::tracking
