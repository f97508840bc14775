#pragma once
// The photometric term on the GPU, per pyramid level (shaders/photometric_reduce.comp): current
// depth and intensity against the reference intensity, gradients and depth. Used like IcpTerm.

#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/reduction/level_reduction.hpp"
#include "vifusion/tracking/photometric_params.hpp"

namespace vifusion::tracking {

struct PhotometricLevelInputs {
  gpu::BufferId current_vertices, current_intensity;                           ///< current frame
  gpu::BufferId reference_intensity, reference_gradients, reference_vertices;  ///< reference (model) view
};

class PhotometricTerm {
 public:
  PhotometricTerm(gpu::GpuContext& context, gpu::CapacityPlan& plan, int levels, const PhotometricOptions& options = {},
                  const LevelReductionOptions& reduction = {});

  void build(const gpu::MemoryArena& arena, std::span<const PhotometricLevelInputs> inputs);
  void record(gpu::CommandRecorder& recorder, int level) const { reduction_.record(recorder, level); }
  /// `use_reference_fill`: PhotometricParams::use_reference_fill.
  void setPose(int level, const SE3d& T_ref_cur, const PinholeCamera& camera, bool use_reference_fill = false) const;
  NormalEquations6 result(int level) const { return reduction_.result(level); }

 private:
  PhotometricOptions options_;
  LevelReduction reduction_;
};

}  // namespace vifusion::tracking
