#pragma once
// The estimator state of one camera frame (Laidlow et al. 2017, §IV-A; DESIGN.md §3) and its local
// parameterisation. This is the only definition of the state; everything else uses it.
//
//   x  = [r_W_C, q_W_C, v_I_S, b_g, b_a, q_I_W] ∈ R³ × S³ × R⁹ × S³
//   δx = [δr, δα, δv, δb_g, δb_a, δg] ∈ R¹⁸  (index constants below)
//
// ⊞ adds the vector parts and perturbs both rotations on the LEFT: q ⊞ δα = exp(δα) ⊗ q, so δα is
// a rotation vector in W (for q_W_C) and δg one in I (for q_I_W). ⊟ is its inverse:
// vector parts subtract, p ⊟ q = log(p ⊗ q⁻¹); (x ⊞ δ) ⊟ x = δ for |δα|, |δg| < π and
// x ⊞ (y ⊟ x) = y always.
//
// q_I_W has three tangent directions although gravity has two degrees of freedom: the rotation about
// the gravity axis is a gauge freedom the paper accepts ("a 3D implementation with gauge freedom").

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace vifusion {

inline constexpr int kStateDim = 18;
inline constexpr int kIdxR = 0;      ///< δr: camera position in W [m]
inline constexpr int kIdxAlpha = 3;  ///< δα: rotation vector of q_W_C, in W [rad]
inline constexpr int kIdxV = 6;      ///< δv: IMU velocity in I [m/s]
inline constexpr int kIdxBg = 9;     ///< δb_g: gyroscope bias [rad/s]
inline constexpr int kIdxBa = 12;    ///< δb_a: accelerometer bias [m/s²]
inline constexpr int kIdxG = 15;     ///< δg: rotation vector of q_I_W, in I [rad]

using Vector18d = Eigen::Matrix<double, kStateDim, 1>;
using Matrix18d = Eigen::Matrix<double, kStateDim, kStateDim>;

/// One frame's state. C++17 aligned new makes EIGEN_MAKE_ALIGNED_OPERATOR_NEW unnecessary here.
struct NavState {
  Eigen::Vector3d r_W_C = Eigen::Vector3d::Zero();            ///< camera position in W [m]
  Eigen::Quaterniond q_W_C = Eigen::Quaterniond::Identity();  ///< camera orientation: rotates C vectors into W
  Eigen::Vector3d v_I_S = Eigen::Vector3d::Zero();            ///< IMU (S) velocity, expressed in I [m/s]
  Eigen::Vector3d b_g = Eigen::Vector3d::Zero();              ///< gyroscope bias [rad/s]
  Eigen::Vector3d b_a = Eigen::Vector3d::Zero();              ///< accelerometer bias [m/s²]
  Eigen::Quaterniond q_I_W = Eigen::Quaterniond::Identity();  ///< rotates W vectors into the gravity-aligned I
};

/// x ⊞ δx. The rotations come back normalised, so repeated updates do not drift off the unit sphere.
NavState boxPlus(const NavState& x, const Vector18d& delta);

/// a ⊟ b, with optional Jacobians in the ⊞ tangent spaces:
///   J_a = ∂((a ⊞ δ) ⊟ b)/∂δ = diag(I, J_l⁻¹(φ_α), I, I, I, J_l⁻¹(φ_g))
///   J_b = ∂(a ⊟ (b ⊞ δ))/∂δ = diag(−I, −J_r⁻¹(φ_α), −I, −I, −I, −J_r⁻¹(φ_g))
/// at δ = 0, where φ_α, φ_g are the rotation parts of the result (so3.hpp for J_l⁻¹, J_r⁻¹).
Vector18d boxMinus(const NavState& a, const NavState& b, Matrix18d* J_a = nullptr, Matrix18d* J_b = nullptr);

}  // namespace vifusion
