#include "vifusion/tracking/icp_term.hpp"

#include <cstring>

#include "vifusion/core/error.hpp"
#include "vifusion/shaders/spirv.hpp"

namespace vifusion::tracking {

IcpTerm::IcpTerm(gpu::GpuContext& context, gpu::CapacityPlan& plan, int levels, const IcpTermOptions& options)
    : context_(context), options_(options) {
  options_.icp.validate();
  if (levels < 1) throw Error("ICP term: at least one level");
  if (options_.workgroups == 0 || options_.workgroup_size < NormalEquations6::kTerms) {
    throw Error("ICP term: need ≥ 1 workgroup of ≥ 29 invocations");
  }
  choice_ = chooseReduction(context.features(), options_.variant, options_.layout);
  for (int l = 0; l < levels; ++l) {
    const std::string prefix = "icp.l" + std::to_string(l) + ".";
    params_ids_.push_back(plan.addBuffer(prefix + "params", sizeof(IcpParams), gpu::MemoryUse::Upload));
    partials_ids_.push_back(plan.addBuffer(
        prefix + "partials", uint64_t{options_.workgroups} * NormalEquations6::kStride * sizeof(float),
        gpu::MemoryUse::Readback));
  }
}

IcpTerm::~IcpTerm() = default;

void IcpTerm::build(const gpu::MemoryArena& arena, std::span<const IcpLevelInputs> inputs) {
  if (inputs.size() != params_ids_.size()) {
    throw Error("ICP term: built with " + std::to_string(inputs.size()) + " levels, planned " +
                std::to_string(params_ids_.size()));
  }
  arena_ = &arena;
  gpu::KernelSpec spec;
  spec.name = choice_.subgroups ? "icp_reduce_subgroup" : "icp_reduce_shared";
  spec.spirv = choice_.subgroups ? shaders::icp_reduce_subgroup : shaders::icp_reduce_shared;
  spec.storage_buffers = 6;
  spec.workgroup_size = {options_.workgroup_size, 1, 1};
  spec.constants = {{3, choice_.contiguous_runs ? 1u : 0u}};
  spec.max_binding_sets = static_cast<uint32_t>(inputs.size());
  kernel_ = gpu::ComputeKernel::create(context_, std::move(spec));
  for (std::size_t l = 0; l < inputs.size(); ++l) {
    const IcpLevelInputs& in = inputs[l];
    sets_.push_back(kernel_->bind({&arena.buffer(in.current_vertices), &arena.buffer(in.current_normals),
                                   &arena.buffer(in.model_vertices), &arena.buffer(in.model_normals),
                                   &arena.buffer(params_ids_[l]), &arena.buffer(partials_ids_[l])}));
  }
}

void IcpTerm::record(gpu::CommandRecorder& recorder, int level) const {
  recorder.dispatch(*kernel_, sets_.at(static_cast<std::size_t>(level)), {options_.workgroups, 1, 1});
  recorder.hostReadBarrier();
}

void IcpTerm::setPose(int level, const SE3d& T_ref_cur, const PinholeCamera& camera) const {
  const IcpParams params = IcpParams::make(T_ref_cur, camera, options_.icp);
  std::memcpy(arena_->buffer(params_ids_.at(static_cast<std::size_t>(level))).mapped, &params, sizeof(params));
}

NormalEquations6 IcpTerm::result(int level) const {
  NormalEquations6 sum;
  sum.addPartials(arena_->buffer(partials_ids_.at(static_cast<std::size_t>(level))).hostSpan<const float>(),
                  options_.workgroups);
  return sum;
}

}  // namespace vifusion::tracking
