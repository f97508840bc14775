#include "vifusion/imu/imu_error.hpp"

#include <Eigen/LU>

#include "vifusion/core/so3.hpp"

namespace vifusion::imu {
namespace {

/// x̂1(x0) and the quantities its Jacobians reuse.
struct Prediction {
  NavState x1;
  ImuDeltas delta;               ///< corrected for x0's biases
  Eigen::Vector3d phi_bias_rad;  ///< ∂ΔR/∂b_g·(b_g0 − b_g_lin): the rotation correction [rad]
  Eigen::Matrix3d R_W_S0;
  Eigen::Matrix3d R_W_S1;
  Eigen::Matrix3d R_I_W0;
  Eigen::Matrix3d R_I_S0;
  Eigen::Vector3d t_W_C0_S0_m;      ///< R_W_C0·t_C_S: lever arm camera → IMU at t0, in W [m]
  Eigen::Vector3d t_W_S1_C1_m;      ///< R_W_S1·t_S_C: lever arm IMU → camera at t1, in W [m]
  Eigen::Vector3d free_motion_I_m;  ///< v_I_S0·Δt + ½·g_I·Δt²: motion without the specific force, in I [m]
};

Prediction propagate(const PreintegratedImu& pre, const NavState& x0, const SE3d& T_S_C,
                     const Eigen::Vector3d& g_I_mps2) {
  Prediction p;
  p.phi_bias_rad = pre.d_R_d_bg * (x0.b_g - pre.b_g_lin_rad_s);
  p.delta = pre.corrected(x0.b_g, x0.b_a);
  const double dt_s = pre.dt_s;

  const SE3d T_W_S0 = SE3d(x0.q_W_C, x0.r_W_C) * T_S_C.inverse();
  const Eigen::Quaterniond q_W_S1 = T_W_S0.quaternion() * p.delta.q_S0_S1;
  p.R_W_S0 = T_W_S0.rotationMatrix();
  p.R_W_S1 = q_W_S1.toRotationMatrix();
  p.R_I_W0 = x0.q_I_W.toRotationMatrix();
  p.R_I_S0 = p.R_I_W0 * p.R_W_S0;
  p.t_W_C0_S0_m = T_W_S0.translation() - x0.r_W_C;
  p.t_W_S1_C1_m = p.R_W_S1 * T_S_C.translation();
  p.free_motion_I_m = x0.v_I_S * dt_s + 0.5 * g_I_mps2 * dt_s * dt_s;

  const Eigen::Vector3d p_W_S1 =
      T_W_S0.translation() + p.R_I_W0.transpose() * p.free_motion_I_m + p.R_W_S0 * p.delta.dp_S0_m;
  const SE3d T_W_C1 = SE3d(q_W_S1, p_W_S1) * T_S_C;
  p.x1.r_W_C = T_W_C1.translation();
  p.x1.q_W_C = T_W_C1.quaternion();
  p.x1.v_I_S = x0.v_I_S + g_I_mps2 * dt_s + p.R_I_S0 * p.delta.dv_S0_mps;
  p.x1.b_g = x0.b_g;
  p.x1.b_a = x0.b_a;
  p.x1.q_I_W = x0.q_I_W;
  return p;
}

/// ∂(x̂1(x0 ⊞ δ) ⊟ x̂1(x0))/∂δ: how each left/additive perturbation of x0 moves the prediction.
Matrix18d predictionJacobian(const PreintegratedImu& pre, const Prediction& p, const Eigen::Vector3d& t_S_C_m) {
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  // A gyro-bias change turns ΔR on the right by J_r(φ_b)·∂ΔR/∂b_g·δb_g, i.e. R_W_S1 on the left by R_W_S1·(that).
  const Eigen::Matrix3d d_theta_S1_d_bg = rightJacobianSO3(p.phi_bias_rad) * pre.d_R_d_bg;
  const Eigen::Vector3d dv_I_mps = p.R_I_S0 * p.delta.dv_S0_mps;

  Matrix18d D = Matrix18d::Zero();
  // Camera position r_W_C1: a left turn δα of q_W_C0 swings every lever arm hanging off it.
  D.block<3, 3>(kIdxR, kIdxR) = I;
  D.block<3, 3>(kIdxR, kIdxAlpha) = -hat(p.t_W_C0_S0_m + p.R_W_S0 * p.delta.dp_S0_m + p.t_W_S1_C1_m);
  D.block<3, 3>(kIdxR, kIdxV) = pre.dt_s * p.R_I_W0.transpose();
  D.block<3, 3>(kIdxR, kIdxBg) = p.R_W_S0 * pre.d_p_d_bg - p.R_W_S1 * hat(t_S_C_m) * d_theta_S1_d_bg;
  D.block<3, 3>(kIdxR, kIdxBa) = p.R_W_S0 * pre.d_p_d_ba;
  D.block<3, 3>(kIdxR, kIdxG) = p.R_I_W0.transpose() * hat(p.free_motion_I_m);
  // Camera orientation q_W_C1.
  D.block<3, 3>(kIdxAlpha, kIdxAlpha) = I;
  D.block<3, 3>(kIdxAlpha, kIdxBg) = p.R_W_S1 * d_theta_S1_d_bg;
  // Velocity v_I_S1.
  D.block<3, 3>(kIdxV, kIdxAlpha) = -hat(dv_I_mps) * p.R_I_W0;
  D.block<3, 3>(kIdxV, kIdxV) = I;
  D.block<3, 3>(kIdxV, kIdxBg) = p.R_I_S0 * pre.d_v_d_bg;
  D.block<3, 3>(kIdxV, kIdxBa) = p.R_I_S0 * pre.d_v_d_ba;
  D.block<3, 3>(kIdxV, kIdxG) = -hat(dv_I_mps);
  // Biases and q_I_W are carried over.
  D.block<3, 3>(kIdxBg, kIdxBg) = I;
  D.block<3, 3>(kIdxBa, kIdxBa) = I;
  D.block<3, 3>(kIdxG, kIdxG) = I;
  return D;
}

}  // namespace

ImuError::ImuError(const ImuOptions& options, const SE3d& T_S_C) : T_S_C_(T_S_C) {
  options.validate();
  g_I_mps2_ = Eigen::Vector3d(0.0, 0.0, -options.noise.gravity_mps2);
  gravity_direction_variance_rad2_per_s_ =
      options.gravity_direction_random_walk * options.gravity_direction_random_walk;
}

NavState ImuError::predict(const PreintegratedImu& pre, const NavState& x0) const {
  return propagate(pre, x0, T_S_C_, g_I_mps2_).x1;
}

Vector18d ImuError::evaluate(const PreintegratedImu& pre, const NavState& x0, const NavState& x1, Matrix18d* J_x0,
                             Matrix18d* J_x1, Matrix18d* information) const {
  const Prediction p = propagate(pre, x0, T_S_C_, g_I_mps2_);
  Matrix18d J_pred;  // ∂((x̂1 ⊞ δ) ⊟ x1)/∂δ
  const Vector18d e = boxMinus(p.x1, x1, &J_pred, J_x1);
  if (J_x0 != nullptr) *J_x0 = J_pred * predictionJacobian(pre, p, T_S_C_.translation());

  if (information != nullptr) {
    // M = ∂e/∂η over the first 15 entries (the header explains each block).
    Matrix15d M = Matrix15d::Zero();
    M.block<3, 3>(kIdxR, kDeltaIdxP) = p.R_W_S0;
    M.block<3, 3>(kIdxR, kDeltaIdxPhi) = -p.R_W_S1 * hat(T_S_C_.translation());
    M.block<3, 3>(kIdxAlpha, kDeltaIdxPhi) = J_pred.block<3, 3>(kIdxAlpha, kIdxAlpha) * p.R_W_S1;
    M.block<3, 3>(kIdxV, kDeltaIdxV) = p.R_I_S0;
    M.block<3, 3>(kIdxBg, kDeltaIdxBg) = -Eigen::Matrix3d::Identity();
    M.block<3, 3>(kIdxBa, kDeltaIdxBa) = -Eigen::Matrix3d::Identity();
    const Matrix15d M_inv = M.partialPivLu().inverse();

    // e_g ≈ J_l⁻¹(e_g)·w with w the gravity direction's walk over Δt, so Cov(e_g)⁻¹ = J_lᵀ·J_l/σ².
    const Eigen::Matrix3d J_l_g = J_pred.block<3, 3>(kIdxG, kIdxG).inverse();
    information->setZero();
    information->topLeftCorner<kDeltaDim, kDeltaDim>() = M_inv.transpose() * pre.information * M_inv;
    information->block<3, 3>(kIdxG, kIdxG) =
        J_l_g.transpose() * J_l_g / (gravity_direction_variance_rad2_per_s_ * pre.dt_s);
    *information = 0.5 * (*information + information->transpose()).eval();
  }
  return e;
}

}  // namespace vifusion::imu
