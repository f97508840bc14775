#pragma once
// The paper's IMU error term (§IV-C), e_IMU = x̂1(x0) ⊟ x1 ∈ R¹⁸, over the state of state.hpp
// (x = [r_W_C, q_W_C, v_I_S, b_g, b_a, q_I_W], δx = [δr, δα, δv, δb_g, δb_a, δg], rotations perturbed on
// the left), with the deltas of preintegration.hpp (whose header states the convention).
//
// Prediction x̂1(x0), through the extrinsics T_S_C (camera → IMU, p_S = T_S_C·p_C) and the inertial frame
// I (origin of W, gravity g_I = (0, 0, −g) [m/s²], q_I_W rotates W vectors into I):
//   T_W_S0 = T_W_C0·T_C_S,  R_I_S0 = R_I_W0·R_W_S0;  deltas corrected to first order for x0's biases;
//   R_W_S1 = R_W_S0·ΔR            (q_I_W cancels: the deltas are relative to S0)
//   p_W_S1 = p_W_S0 + R_I_W0ᵀ·(v_I_S0·Δt + ½·g_I·Δt²) + R_W_S0·Δp
//   v_I_S1 = v_I_S0 + g_I·Δt + R_I_S0·Δv
//   T_W_C1 = T_W_S1·T_S_C;  b_g, b_a and q_I_W predicted constant (x0's).
//
// Information: the inverse covariance of e at the given states.
//  - The first 15 entries: e ≈ M·η with η the preintegration error (δp, δφ, δv, bias walk) and
//    M = ∂e/∂η (δp moves r by R_W_S0·δp; δφ turns S1, so q_W_C by R_W_S1·δφ and r through the lever arm;
//    δv moves v by R_I_S0·δv; the walk b(t1) − b(t0) enters e_b = b0 − b1 with −I), so the information is
//    M⁻ᵀ·Σ_η⁻¹·M⁻¹: bias random walk included, and the walk's correlation with the deltas kept.
//    η's δφ perturbs the uncorrected ΔR; treating it as a perturbation of the corrected one ignores a
//    rotation by ∂ΔR/∂b_g·δb_g ≤ reintegrate_above_rad = 1e-4 rad.
//  - δg: q_I_W is a constant of the world and is predicted exactly, so e_g carries no measurement noise and
//    its information would be infinite. It gets the variance of a random walk of the gravity direction,
//    ImuOptions::gravity_direction_random_walk = 1e-4 rad/√s: at 30 Hz the weight 1/(σ²·Δt) ≈ 3e9 rad⁻² is
//    of the order of the position block's (σ_a²·Δt³/3)⁻¹ ≈ 1e9 m⁻², so it pins q_I_W from frame to frame
//    without making the 18×18 system ill-conditioned; unobserved, the direction could wander 0.3° an hour.
// Gauss–Newton treats the information as constant within an iteration.

#include <Eigen/Core>

#include "vifusion/core/se3.hpp"
#include "vifusion/core/state.hpp"
#include "vifusion/imu/imu_options.hpp"
#include "vifusion/imu/preintegration.hpp"

namespace vifusion::imu {

class ImuError {
 public:
  /// @param T_S_C  camera → IMU (Kalibr's T_cam_imu is its inverse, T_C_S)
  /// @throws vifusion::Error from options.validate().
  ImuError(const ImuOptions& options, const SE3d& T_S_C);

  /// x̂1(x0): the state at pre.t1_ns predicted from x0 at pre.t0_ns.
  NavState predict(const PreintegratedImu& pre, const NavState& x0) const;

  /// e = x̂1(x0) ⊟ x1, and optionally (nullptr skips):
  ///   J_x0 = ∂e(x0 ⊞ δ, x1)/∂δ,  J_x1 = ∂e(x0, x1 ⊞ δ)/∂δ  at δ = 0, in the ⊞ tangent spaces;
  ///   information = Cov(e)⁻¹ as described above (symmetric positive definite).
  /// The deltas are corrected to first order for x0's biases; check pre.needsReintegration(x0.b_g) first.
  /// Allocates nothing.
  Vector18d evaluate(const PreintegratedImu& pre, const NavState& x0, const NavState& x1, Matrix18d* J_x0 = nullptr,
                     Matrix18d* J_x1 = nullptr, Matrix18d* information = nullptr) const;

 private:
  SE3d T_S_C_;
  Eigen::Vector3d g_I_mps2_;
  double gravity_direction_variance_rad2_per_s_;  ///< (gravity_direction_random_walk)² [rad²/s]
};

}  // namespace vifusion::imu
