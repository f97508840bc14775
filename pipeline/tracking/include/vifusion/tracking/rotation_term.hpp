#pragma once
// The rotation-only pre-alignment on the GPU (shaders/rotation_reduce.comp), per pyramid level: the
// current intensity against the previous frame's intensity and gradients. Used like PhotometricTerm; the
// rotation block of its normal equations (rows 3..5) holds the system over φ, R_prev_cur ← exp(φ)·R_prev_cur.

#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/reduction/level_reduction.hpp"
#include "vifusion/tracking/photometric_params.hpp"
#include "vifusion/tracking/rotation_params.hpp"

namespace vifusion::tracking {

struct RotationInputs {
  gpu::BufferId current_intensity;                       ///< current frame, float
  gpu::BufferId previous_intensity, previous_gradients;  ///< previous frame, float and GradientPixel
};

class RotationTerm {
 public:
  RotationTerm(gpu::GpuContext& context, gpu::CapacityPlan& plan, int levels, const PhotometricOptions& options = {},
               const LevelReductionOptions& reduction = {});

  void build(const gpu::MemoryArena& arena, std::span<const RotationInputs> inputs);
  void record(gpu::CommandRecorder& recorder, int level) const { reduction_.record(recorder, level); }
  void setRotation(int level, const Eigen::Quaterniond& q_prev_cur, const PinholeCamera& camera) const;
  NormalEquations6 result(int level) const { return reduction_.result(level); }

 private:
  PhotometricOptions options_;
  LevelReduction reduction_;
};

}  // namespace vifusion::tracking
