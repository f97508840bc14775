#include "vifusion/reduction/level_reduction.hpp"

#include <algorithm>
#include <cstring>
#include <thread>

#include "vifusion/core/error.hpp"

namespace vifusion {

LevelReduction::LevelReduction(gpu::GpuContext& context, gpu::CapacityPlan& plan, int levels,
                               LevelReductionKernel kernel, const LevelReductionOptions& options)
    : context_(context), kernel_spec_(std::move(kernel)), options_(options) {
  const std::string& name = kernel_spec_.name;
  if (levels < 1) throw Error(name + ": needs at least one level");
  const bool cpu = context.features().device_type == VK_PHYSICAL_DEVICE_TYPE_CPU;
  if (options_.workgroups == 0) {
    options_.workgroups = cpu ? std::max(2u, std::thread::hardware_concurrency()) : 16u;
  }
  if (options_.workgroup_size == 0) options_.workgroup_size = cpu ? 64u : 128u;
  if (options_.workgroup_size < NormalEquations6::kTerms) {
    throw Error(name + ": needs workgroups of ≥ " + std::to_string(NormalEquations6::kTerms) + " invocations");
  }
  choice_ = chooseReduction(context.features(), options_.variant, options_.layout);
  for (int l = 0; l < levels; ++l) {
    const std::string prefix = name + ".l" + std::to_string(l) + ".";
    params_ids_.push_back(plan.addBuffer(prefix + "params", kernel_spec_.params_bytes, gpu::MemoryUse::Upload));
    partials_ids_.push_back(plan.addBuffer(prefix + "partials",
                                           uint64_t{options_.workgroups} * NormalEquations6::kStride * sizeof(float),
                                           gpu::MemoryUse::Readback));
  }
}

LevelReduction::~LevelReduction() = default;

void LevelReduction::build(const gpu::MemoryArena& arena, std::span<const std::vector<gpu::BufferId>> inputs_per_level) {
  const std::string& name = kernel_spec_.name;
  if (inputs_per_level.size() != params_ids_.size()) {
    throw Error(name + ": built with " + std::to_string(inputs_per_level.size()) + " levels, planned " +
                std::to_string(params_ids_.size()));
  }
  arena_ = &arena;
  gpu::KernelSpec spec;
  spec.name = name + (choice_.subgroups ? "_subgroup" : "_shared");
  spec.spirv = choice_.subgroups ? kernel_spec_.subgroup_spirv : kernel_spec_.shared_spirv;
  spec.storage_buffers = kernel_spec_.input_buffers + 2;
  spec.workgroup_size = {options_.workgroup_size, 1, 1};
  spec.constants = {{3, choice_.contiguous_runs ? 1u : 0u}};
  spec.max_binding_sets = static_cast<uint32_t>(inputs_per_level.size());
  kernel_ = gpu::ComputeKernel::create(context_, std::move(spec));
  for (std::size_t l = 0; l < inputs_per_level.size(); ++l) {
    if (inputs_per_level[l].size() != kernel_spec_.input_buffers) {
      throw Error(name + ": level " + std::to_string(l) + " has " + std::to_string(inputs_per_level[l].size()) +
                  " inputs, the kernel reads " + std::to_string(kernel_spec_.input_buffers));
    }
    std::vector<const gpu::GpuBuffer*> buffers;
    for (gpu::BufferId id : inputs_per_level[l]) buffers.push_back(&arena.buffer(id));
    buffers.push_back(&arena.buffer(params_ids_[l]));
    buffers.push_back(&arena.buffer(partials_ids_[l]));
    sets_.push_back(kernel_->bind(buffers));
  }
}

void LevelReduction::record(gpu::CommandRecorder& recorder, int level) const {
  recorder.dispatch(*kernel_, sets_.at(static_cast<std::size_t>(level)), {options_.workgroups, 1, 1});
  recorder.hostReadBarrier();
}

void LevelReduction::writeParams(int level, const void* params) const {
  std::memcpy(arena_->buffer(params_ids_.at(static_cast<std::size_t>(level))).mapped, params, kernel_spec_.params_bytes);
}

NormalEquations6 LevelReduction::result(int level) const {
  NormalEquations6 sum;
  sum.addPartials(arena_->buffer(partials_ids_.at(static_cast<std::size_t>(level))).hostSpan<const float>(),
                  options_.workgroups);
  return sum;
}

}  // namespace vifusion
