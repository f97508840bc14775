#pragma once
// The point-to-plane ICP term on the GPU, per pyramid level: one kernel that associates, weights
// and reduces in a single pass. Record each level once; before each Gauss-Newton iteration write
// the pose with setPose() (a mapped buffer), submit, then read result().

#include <memory>
#include <span>
#include <vector>

#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/gpu/capacity_plan.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/gpu/compute_kernel.hpp"
#include "vifusion/gpu/memory_arena.hpp"
#include "vifusion/reduction/normal_equations.hpp"
#include "vifusion/reduction/row_reducer.hpp"
#include "vifusion/tracking/icp_params.hpp"

namespace vifusion::tracking {

struct IcpTermOptions {
  IcpOptions icp;
  uint32_t workgroups = 16;
  uint32_t workgroup_size = 128;
  ReductionVariant variant = ReductionVariant::Auto;
  ReductionLayout layout = ReductionLayout::Auto;
};

/// Buffers (from the capacity plan) the term reads at one level.
struct IcpLevelInputs {
  gpu::BufferId current_vertices, current_normals;  ///< current camera frame
  gpu::BufferId model_vertices, model_normals;      ///< reference (model) camera frame
};

class IcpTerm {
 public:
  /// Declares one parameter (upload) and one partial (readback) buffer per level.
  IcpTerm(gpu::GpuContext& context, gpu::CapacityPlan& plan, int levels, const IcpTermOptions& options);
  ~IcpTerm();

  void build(const gpu::MemoryArena& arena, std::span<const IcpLevelInputs> inputs);
  void record(gpu::CommandRecorder& recorder, int level) const;
  /// Writes T_ref_cur and the level's intrinsics for the next submission of `level`.
  void setPose(int level, const SE3d& T_ref_cur, const PinholeCamera& camera) const;
  /// Normal equations of the last completed submission of `level`, summed in double.
  NormalEquations6 result(int level) const;

 private:
  gpu::GpuContext& context_;
  IcpTermOptions options_;
  ReductionChoice choice_;
  std::vector<gpu::BufferId> params_ids_, partials_ids_;
  const gpu::MemoryArena* arena_ = nullptr;
  std::unique_ptr<gpu::ComputeKernel> kernel_;
  std::vector<gpu::BindingSet> sets_;
};

}  // namespace vifusion::tracking
