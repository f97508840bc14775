#pragma once
// Rotations as Hamilton unit quaternions (Eigen::Quaterniond: w + xi + yj + zk, ij = k), the
// exponential/logarithm maps of SO(3) and their Jacobians.
//
// Perturbation convention (paper §IV-A, DESIGN.md §3): rotations are perturbed on the LEFT,
//   q ⊞ δα = exp(δα) ⊗ q,      p ⊟ q = log(p ⊗ q⁻¹),
// so δα is expressed in the frame q rotates INTO (for q_W_C: the world frame W).
//
// Jacobians of the exponential map, φ ∈ R³ [rad], δ → 0:
//   exp(φ + δ) = exp(J_l(φ)·δ) ⊗ exp(φ)       J_l = leftJacobianSO3(φ)
//   exp(φ + δ) = exp(φ) ⊗ exp(J_r(φ)·δ)       J_r = rightJacobianSO3(φ)
//   log(exp(δ) ⊗ exp(φ)) = φ + J_l⁻¹(φ)·δ     leftJacobianInvSO3(φ)
//   log(exp(φ) ⊗ exp(δ)) = φ + J_r⁻¹(φ)·δ     rightJacobianInvSO3(φ)
// with J_l(φ) = J_r(−φ) = J_r(φ)ᵀ and J_l(φ) = R(φ)·J_r(φ).
// Every function is exact for all angles and uses Taylor series near θ = 0 where the closed forms
// cancel catastrophically; the inverse Jacobians are singular at θ = 2π and are meant for
// θ ∈ [0, π], the range logSO3() returns.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace vifusion {

/// Skew-symmetric matrix with hat(v)·w = v × w.
Eigen::Matrix3d hat(const Eigen::Vector3d& v);

/// Exponential map: rotation vector ω (axis · angle [rad]) to the unit quaternion rotating by |ω| about ω.
Eigen::Quaterniond expSO3(const Eigen::Vector3d& omega);

/// Logarithm: the rotation vector ω with |ω| ∈ [0, π] and expSO3(ω) = ±q. q and −q give the same
/// result; at exactly π either of the two opposite vectors may come back. Scale-invariant in q, so a
/// quaternion slightly off unit norm still yields the rotation it represents.
Eigen::Vector3d logSO3(const Eigen::Quaterniond& q);

Eigen::Matrix3d leftJacobianSO3(const Eigen::Vector3d& phi);
Eigen::Matrix3d leftJacobianInvSO3(const Eigen::Vector3d& phi);
Eigen::Matrix3d rightJacobianSO3(const Eigen::Vector3d& phi);
Eigen::Matrix3d rightJacobianInvSO3(const Eigen::Vector3d& phi);

}  // namespace vifusion
