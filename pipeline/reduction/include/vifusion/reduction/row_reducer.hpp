#pragma once
// GPU reduction of residual rows [J (6), r, w] into normal equations, and its CPU reference.
// The kernel variant follows the device: subgroup arithmetic where available, a shared-memory
// tree otherwise; contiguous runs per invocation on CPU devices, a grid stride on GPUs.

#include <cstdint>
#include <memory>
#include <span>

#include "vifusion/gpu/capacity_plan.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/gpu/compute_kernel.hpp"
#include "vifusion/gpu/gpu_context.hpp"
#include "vifusion/gpu/memory_arena.hpp"
#include "vifusion/reduction/normal_equations.hpp"

namespace vifusion {

/// One residual row as the kernel reads it: two vec4 (J0..J3), (J4, J5, r, w).
struct ResidualRow {
  float J[6] = {};
  float r = 0.0f;
  float w = 0.0f;  ///< inverse variance × robust weight; 0 marks an outlier
};
static_assert(sizeof(ResidualRow) == 32);

/// CPU reference: the same sums in double.
NormalEquations6 reduceRowsCpu(std::span<const ResidualRow> rows);

enum class ReductionVariant { Auto, Subgroup, SharedMemory };
enum class ReductionLayout { Auto, ContiguousRuns, GridStride };

/// The kernel variant every reducing kernel (rows, ICP, photometric) uses on a device.
struct ReductionChoice {
  bool subgroups = false;       ///< subgroup arithmetic (else a shared-memory tree)
  bool contiguous_runs = true;  ///< each invocation walks a run of rows (else a grid stride)
};
/// Auto picks subgroups when the device has them and contiguous runs on CPU devices (lavapipe),
/// where streaming through memory beats coalescing. Throws if Subgroup is forced but unsupported.
ReductionChoice chooseReduction(const gpu::GpuFeatures& features, ReductionVariant variant, ReductionLayout layout);

struct RowReducerOptions {
  uint32_t max_rows = 640 * 480;  ///< capacity of the row buffer
  uint32_t workgroups = 16;       ///< partials the host sums (≥ 1)
  uint32_t workgroup_size = 128;  ///< invocations per workgroup (≥ 31)
  ReductionVariant variant = ReductionVariant::Auto;
  ReductionLayout layout = ReductionLayout::Auto;

  /// Throws vifusion::Error naming the bad field.
  void validate() const;
};

class RowReducer {
 public:
  /// Declares the row (upload) and partial (readback) buffers in `plan`.
  RowReducer(gpu::GpuContext& context, gpu::CapacityPlan& plan, const RowReducerOptions& options);

  /// Creates the kernel and its binding set once the arena exists.
  void build(const gpu::MemoryArena& arena);

  /// Host-writable rows (persistently mapped upload buffer).
  std::span<ResidualRow> rows() const;
  /// Records the reduction of the first `row_count` rows.
  void record(gpu::CommandRecorder& recorder, uint32_t row_count) const;
  /// Sums the partials of the last completed run in double.
  NormalEquations6 result() const;

  bool usesSubgroups() const { return choice_.subgroups; }
  bool usesContiguousRuns() const { return choice_.contiguous_runs; }

 private:
  gpu::GpuContext& context_;
  RowReducerOptions options_;
  ReductionChoice choice_;
  gpu::BufferId rows_id_;
  gpu::BufferId partials_id_;
  const gpu::GpuBuffer* rows_ = nullptr;
  const gpu::GpuBuffer* partials_ = nullptr;
  std::unique_ptr<gpu::ComputeKernel> kernel_;
  gpu::BindingSet binding_;
};

}  // namespace vifusion
