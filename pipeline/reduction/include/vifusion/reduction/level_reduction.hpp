#pragma once
// A kernel that reduces items straight into normal equations, once per pyramid level: the shape
// shared by the dense tracking terms (ICP, photometric). Per level it owns a parameter buffer
// (host-written, std430) and a partials buffer; each level's dispatch is recorded once and only
// the parameters change between Gauss-Newton iterations.

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "vifusion/gpu/capacity_plan.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/gpu/compute_kernel.hpp"
#include "vifusion/gpu/memory_arena.hpp"
#include "vifusion/reduction/normal_equations.hpp"
#include "vifusion/reduction/row_reducer.hpp"

namespace vifusion {

struct LevelReductionOptions {
  /// Partials the host sums; 0 = by device: 16 on GPUs, one per hardware thread (≥ 2) on CPU devices.
  uint32_t workgroups = 0;
  /// ≥ 31 (one invocation per reduced term in the final step); 0 = by device: 128 on GPUs, 64 on
  /// CPU devices. lavapipe runs fewer, longer invocations faster (measured at 320×240: ICP
  /// 3.1-3.7 → 2.1-2.4 CPU-ms per evaluation with 2 × 64 instead of 16 × 128; ≈ 10 % at 640×480).
  /// The grid only reassociates fp32 sums, but the bench trajectory is sensitive to that: ATE at
  /// 320×240 ranged 10.0-10.7 mm over six grids (tests/bench/README.md).
  uint32_t workgroup_size = 0;
  ReductionVariant variant = ReductionVariant::Auto;
  ReductionLayout layout = ReductionLayout::Auto;
};

struct LevelReductionKernel {
  std::string name;  ///< e.g. "icp_reduce"
  std::span<const uint32_t> subgroup_spirv;
  std::span<const uint32_t> shared_spirv;
  uint32_t input_buffers = 0;  ///< bindings 0..n−1; then params, then partials
  uint32_t params_bytes = 0;   ///< size of the std430 parameter struct
};

class LevelReduction {
 public:
  /// Declares `levels` parameter (upload) and partial (readback) buffers named "<name>.l<i>.*".
  LevelReduction(gpu::GpuContext& context, gpu::CapacityPlan& plan, int levels, LevelReductionKernel kernel,
                 const LevelReductionOptions& options);
  ~LevelReduction();

  /// Creates the kernel and binds each level's inputs (in binding order) once the arena exists.
  void build(const gpu::MemoryArena& arena, std::span<const std::vector<gpu::BufferId>> inputs_per_level);
  void record(gpu::CommandRecorder& recorder, int level) const;
  /// Copies params_bytes from `params` into the level's mapped parameter buffer.
  void writeParams(int level, const void* params) const;
  /// Normal equations of the last completed submission of `level`, summed in double.
  NormalEquations6 result(int level) const;
  bool usesSubgroups() const { return choice_.subgroups; }

 private:
  gpu::GpuContext& context_;
  LevelReductionKernel kernel_spec_;
  LevelReductionOptions options_;
  ReductionChoice choice_;
  std::vector<gpu::BufferId> params_ids_, partials_ids_;
  const gpu::MemoryArena* arena_ = nullptr;
  std::unique_ptr<gpu::ComputeKernel> kernel_;
  std::vector<gpu::BindingSet> sets_;
};

}  // namespace vifusion
