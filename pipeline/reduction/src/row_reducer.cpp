#include "vifusion/reduction/row_reducer.hpp"

#include "vifusion/core/error.hpp"
#include "vifusion/shaders/spirv.hpp"

namespace vifusion {

NormalEquations6 reduceRowsCpu(std::span<const ResidualRow> rows) {
  NormalEquations6 sum;
  for (const ResidualRow& row : rows) {
    Eigen::Matrix<double, 6, 1> J;
    for (int i = 0; i < 6; ++i) J(i) = row.J[i];
    sum.addCandidate();
    sum.addRow(J, row.r, row.w);
  }
  return sum;
}

void RowReducerOptions::validate() const {
  if (max_rows == 0) throw Error("row reducer: max_rows must be at least 1");
  if (workgroups == 0) throw Error("row reducer: workgroups must be at least 1");
  if (workgroup_size < NormalEquations6::kTerms) {
    throw Error("row reducer: workgroup_size " + std::to_string(workgroup_size) + " is below " +
                std::to_string(NormalEquations6::kTerms) + " (one invocation per reduced term)");
  }
}

ReductionChoice chooseReduction(const gpu::GpuFeatures& features, ReductionVariant variant, ReductionLayout layout) {
  ReductionChoice choice;
  switch (variant) {
    case ReductionVariant::Auto: choice.subgroups = features.subgroup_arithmetic; break;
    case ReductionVariant::Subgroup:
      if (!features.subgroup_arithmetic) {
        throw Error("reduction: subgroup variant requested but '" + features.device_name + "' has no subgroup arithmetic");
      }
      choice.subgroups = true;
      break;
    case ReductionVariant::SharedMemory: choice.subgroups = false; break;
  }
  choice.contiguous_runs = layout == ReductionLayout::Auto ? features.device_type == VK_PHYSICAL_DEVICE_TYPE_CPU
                                                           : layout == ReductionLayout::ContiguousRuns;
  return choice;
}

RowReducer::RowReducer(gpu::GpuContext& context, gpu::CapacityPlan& plan, const RowReducerOptions& options)
    : context_(context), options_(options) {
  options_.validate();
  choice_ = chooseReduction(context.features(), options_.variant, options_.layout);
  rows_id_ = plan.addBuffer("reduction.rows", uint64_t{options_.max_rows} * sizeof(ResidualRow), gpu::MemoryUse::Upload);
  partials_id_ = plan.addBuffer("reduction.partials",
                                uint64_t{options_.workgroups} * NormalEquations6::kStride * sizeof(float),
                                gpu::MemoryUse::Readback);
}

void RowReducer::build(const gpu::MemoryArena& arena) {
  rows_ = &arena.buffer(rows_id_);
  partials_ = &arena.buffer(partials_id_);
  gpu::KernelSpec spec;
  spec.name = choice_.subgroups ? "reduce_rows_subgroup" : "reduce_rows_shared";
  spec.spirv = choice_.subgroups ? shaders::reduce_rows_subgroup : shaders::reduce_rows_shared;
  spec.storage_buffers = 2;
  spec.push_constant_bytes = sizeof(uint32_t);
  spec.workgroup_size = {options_.workgroup_size, 1, 1};
  spec.constants = {{3, choice_.contiguous_runs ? 1u : 0u}};
  kernel_ = gpu::ComputeKernel::create(context_, std::move(spec));
  binding_ = kernel_->bind({rows_, partials_});
}

std::span<ResidualRow> RowReducer::rows() const { return rows_->hostSpan<ResidualRow>(); }

void RowReducer::record(gpu::CommandRecorder& recorder, uint32_t row_count) const {
  if (row_count > options_.max_rows) {
    throw Error("row reducer: " + std::to_string(row_count) + " rows exceed the planned " +
                std::to_string(options_.max_rows));
  }
  recorder.dispatch(*kernel_, binding_, {options_.workgroups, 1, 1}, row_count);
  recorder.hostReadBarrier();
}

NormalEquations6 RowReducer::result() const {
  NormalEquations6 sum;
  sum.addPartials(partials_->hostSpan<const float>(), options_.workgroups);
  return sum;
}

}  // namespace vifusion
