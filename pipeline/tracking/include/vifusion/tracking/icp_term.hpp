#pragma once
// The point-to-plane ICP term on the GPU, per pyramid level: one kernel that associates, weights
// and reduces in a single pass (shaders/icp_reduce.comp). Record each level once; before each
// Gauss-Newton iteration write the pose with setPose(), submit, then read result().

#include <string>

#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/reduction/level_reduction.hpp"
#include "vifusion/tracking/icp_params.hpp"

namespace vifusion::tracking {

/// Buffers (from the capacity plan) the term reads at one level.
struct IcpLevelInputs {
  gpu::BufferId current_vertices, current_normals;  ///< current camera frame
  gpu::BufferId model_vertices, model_normals;      ///< reference (model) camera frame
};

class IcpTerm {
 public:
  /// `name` prefixes the term's buffers in the plan: one plan may hold several instances (the tracker's,
  /// loop closure's registration) under different names.
  IcpTerm(gpu::GpuContext& context, gpu::CapacityPlan& plan, int levels, const IcpOptions& options = {},
          const LevelReductionOptions& reduction = {}, const std::string& name = "icp_reduce");

  void build(const gpu::MemoryArena& arena, std::span<const IcpLevelInputs> inputs);
  void record(gpu::CommandRecorder& recorder, int level) const { reduction_.record(recorder, level); }
  /// Writes T_ref_cur and the level's intrinsics for the next submission of `level`.
  void setPose(int level, const SE3d& T_ref_cur, const PinholeCamera& camera) const;
  NormalEquations6 result(int level) const { return reduction_.result(level); }

 private:
  IcpOptions options_;
  LevelReduction reduction_;
};

}  // namespace vifusion::tracking
