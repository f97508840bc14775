#pragma once
// Rigid transforms SE(3) as a unit Hamilton quaternion and a translation. A transform named T_a_b maps
// points from frame b to frame a: p_a = T_a_b · p_b = R_a_b·p_b + t_a_b, and T_a_b · T_b_c = T_a_c.
//
// Twists are ξ = [ρ; φ] ∈ R⁶: translation part ρ [m] FIRST, rotation vector φ [rad] SECOND
// (Barfoot's and Sophus' order). exp(ξ) = (expSO3(φ), J_l(φ)·ρ) with J_l the SO(3) left Jacobian.
//
// Jacobians of the exponential map, δ → 0 (same pattern as so3.hpp):
//   exp(ξ + δ) = exp(J_l(ξ)·δ) · exp(ξ)      leftJacobian(ξ)
//   exp(ξ + δ) = exp(ξ) · exp(J_r(ξ)·δ)      rightJacobian(ξ)
//   log(exp(δ) · T) = log(T) + J_l⁻¹(log T)·δ,   log(T · exp(δ)) = log(T) + J_r⁻¹(log T)·δ
// and the adjoint moves a right perturbation to the left: T · exp(δ) = exp(Ad(T)·δ) · T.
// J_l(ξ) = J_r(−ξ) = Ad(exp(ξ))·J_r(ξ).
//
// For ICP and pose graphs both perturbation sides are offered; note that the NavState (state.hpp)
// perturbs position additively and orientation on the left, which is neither SE(3) convention.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace vifusion {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

class SE3d {
 public:
  /// Identity.
  SE3d() = default;
  /// From a rotation (normalised here, so callers may pass a nearly unit quaternion) and a translation [m].
  SE3d(const Eigen::Quaterniond& q, const Eigen::Vector3d& t);

  /// From a quaternion that was normalised where it was made (a pose read back from a file), kept bit for bit:
  /// normalising it again could change its last bits, and a saved map read and saved again must not change.
  static SE3d fromUnitQuaternion(const Eigen::Quaterniond& q_unit, const Eigen::Vector3d& t);

  static SE3d exp(const Vector6d& xi);
  /// The twist ξ = [ρ; φ] with |φ| ∈ [0, π] and exp(ξ) = *this.
  Vector6d log() const;

  SE3d inverse() const;
  /// T_a_b · T_b_c = T_a_c. The product quaternion is re-normalised so long chains do not drift.
  SE3d operator*(const SE3d& T_b_c) const;
  /// p_a = T_a_b · p_b.
  Eigen::Vector3d operator*(const Eigen::Vector3d& p_b) const;

  /// Homogeneous 4×4 matrix [R t; 0 1].
  Eigen::Matrix4d matrix() const;
  Eigen::Matrix3d rotationMatrix() const { return q_.toRotationMatrix(); }
  const Eigen::Quaterniond& quaternion() const { return q_; }
  const Eigen::Vector3d& translation() const { return t_; }
  Eigen::Vector3d& translation() { return t_; }
  /// Replaces the rotation, normalising q.
  void setQuaternion(const Eigen::Quaterniond& q);

  /// Ad(T) = [R, hat(t)·R; 0, R] for ξ = [ρ; φ]: T · exp(δ) · T⁻¹ = exp(Ad(T)·δ).
  Matrix6d adjoint() const;

  /// ∂(exp(δ) · T_a_b · p_b)/∂δ at δ = 0, i.e. [I, −hat(T_a_b·p_b)] (left perturbation; for ICP).
  Eigen::Matrix<double, 3, 6> pointJacobianLeft(const Eigen::Vector3d& p_b) const;
  /// ∂(T_a_b · exp(δ) · p_b)/∂δ at δ = 0, i.e. R_a_b·[I, −hat(p_b)] (right perturbation).
  Eigen::Matrix<double, 3, 6> pointJacobianRight(const Eigen::Vector3d& p_b) const;

  static Matrix6d leftJacobian(const Vector6d& xi);
  static Matrix6d leftJacobianInv(const Vector6d& xi);
  static Matrix6d rightJacobian(const Vector6d& xi);
  static Matrix6d rightJacobianInv(const Vector6d& xi);

 private:
  Eigen::Quaterniond q_ = Eigen::Quaterniond::Identity();  ///< R_a_b, unit norm
  Eigen::Vector3d t_ = Eigen::Vector3d::Zero();            ///< t_a_b: origin of b in a [m]
};

}  // namespace vifusion
