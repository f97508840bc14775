#pragma once
// The dense terms' normal equations in the estimator's coordinates. The GPU reduces them over a LEFT
// twist of the current camera in the REFERENCE camera (the map prediction's view, rendered at T_W_ref):
// T_ref_cur ← exp(ξ)·T_ref_cur, ξ = [ρ; φ]. The state perturbs x1's pose as r_W_C ← r_W_C + δr and
// q_W_C ← exp(δα)·q_W_C (state.hpp). To first order
//   ξ = Ad(T_ref_W)·[δr + hat(r_W_C)·δα; δα] = A·[δr; δα],
// so H_state = Aᵀ·H_ref·A and b_state = Aᵀ·b_ref (b = JᵀWr, step −H⁻¹b in both).

#include <Eigen/Core>

#include "vifusion/core/se3.hpp"

namespace vifusion::estimator {

/// A = ∂ξ/∂[δr; δα] at the pose T_W_C, for a reference camera at T_W_ref.
Matrix6d referenceTwistPerStatePose(const SE3d& T_W_ref, const SE3d& T_W_C);

/// Normal equations over [δr, δα] of x1's pose.
struct PoseSystem {
  Matrix6d H = Matrix6d::Zero();  ///< information [1/m², 1/(m·rad), 1/rad²]
  Vector6d b = Vector6d::Zero();  ///< gradient JᵀWr
  double inliers = 0.0;           ///< residual rows that passed the terms' outlier tests (how well the view fits)
};

/// Converts normal equations over the reference-camera twist into the state's pose coordinates.
PoseSystem toStatePose(const Matrix6d& H_ref, const Vector6d& b_ref, const SE3d& T_W_ref, const SE3d& T_W_C);

}  // namespace vifusion::estimator
