#include "vifusion/core/se3.hpp"

#include "rotation_series.hpp"
#include "vifusion/core/so3.hpp"

namespace vifusion {
namespace {

/// The off-diagonal block Q(ρ, φ) of the SE(3) left Jacobian (Barfoot, State Estimation for
/// Robotics, eq. 7.86): the series Σ (φ^)ⁿ ρ^ (φ^)ᵐ / (n + m + 2)! in closed form.
Eigen::Matrix3d leftJacobianQ(const Eigen::Vector3d& rho, const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  const Eigen::Matrix3d P = hat(phi);
  const Eigen::Matrix3d R = hat(rho);
  const Eigen::Matrix3d PR = P * R;
  const Eigen::Matrix3d RP = R * P;
  const Eigen::Matrix3d PRP = PR * P;
  const Eigen::Matrix3d PP = P * P;
  return 0.5 * R + detail::angleMinusSinOverAngleCubed(theta) * (PR + RP + PRP) +
         detail::se3QCoefficient2(theta) * (PP * R + RP * P - 3.0 * PRP) +
         detail::se3QCoefficient3(theta) * (PRP * P + PP * RP);
}

}  // namespace

SE3d::SE3d(const Eigen::Quaterniond& q, const Eigen::Vector3d& t) : q_(q.normalized()), t_(t) {}

SE3d SE3d::fromUnitQuaternion(const Eigen::Quaterniond& q_unit, const Eigen::Vector3d& t) {
  SE3d T;
  T.q_ = q_unit;
  T.t_ = t;
  return T;
}

SE3d SE3d::exp(const Vector6d& xi) {
  const Eigen::Vector3d phi = xi.tail<3>();
  return SE3d(expSO3(phi), leftJacobianSO3(phi) * xi.head<3>());
}

Vector6d SE3d::log() const {
  const Eigen::Vector3d phi = logSO3(q_);
  Vector6d xi;
  xi << leftJacobianInvSO3(phi) * t_, phi;
  return xi;
}

SE3d SE3d::inverse() const {
  const Eigen::Quaterniond q_inv = q_.conjugate();
  return SE3d(q_inv, -(q_inv * t_));
}

SE3d SE3d::operator*(const SE3d& T_b_c) const { return SE3d(q_ * T_b_c.q_, q_ * T_b_c.t_ + t_); }

Eigen::Vector3d SE3d::operator*(const Eigen::Vector3d& p_b) const { return q_ * p_b + t_; }

Eigen::Matrix4d SE3d::matrix() const {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = q_.toRotationMatrix();
  m.topRightCorner<3, 1>() = t_;
  return m;
}

void SE3d::setQuaternion(const Eigen::Quaterniond& q) { q_ = q.normalized(); }

Matrix6d SE3d::adjoint() const {
  const Eigen::Matrix3d R = q_.toRotationMatrix();
  Matrix6d ad;
  ad << R, hat(t_) * R, Eigen::Matrix3d::Zero(), R;
  return ad;
}

Eigen::Matrix<double, 3, 6> SE3d::pointJacobianLeft(const Eigen::Vector3d& p_b) const {
  Eigen::Matrix<double, 3, 6> J;
  J << Eigen::Matrix3d::Identity(), -hat(*this * p_b);
  return J;
}

Eigen::Matrix<double, 3, 6> SE3d::pointJacobianRight(const Eigen::Vector3d& p_b) const {
  const Eigen::Matrix3d R = q_.toRotationMatrix();
  Eigen::Matrix<double, 3, 6> J;
  J << R, -R * hat(p_b);
  return J;
}

Matrix6d SE3d::leftJacobian(const Vector6d& xi) {
  const Eigen::Vector3d rho = xi.head<3>();
  const Eigen::Vector3d phi = xi.tail<3>();
  const Eigen::Matrix3d J = leftJacobianSO3(phi);
  Matrix6d jac;
  jac << J, leftJacobianQ(rho, phi), Eigen::Matrix3d::Zero(), J;
  return jac;
}

Matrix6d SE3d::leftJacobianInv(const Vector6d& xi) {
  // Block-triangular inverse of [J Q; 0 J].
  const Eigen::Vector3d rho = xi.head<3>();
  const Eigen::Vector3d phi = xi.tail<3>();
  const Eigen::Matrix3d J_inv = leftJacobianInvSO3(phi);
  Matrix6d jac;
  jac << J_inv, -J_inv * leftJacobianQ(rho, phi) * J_inv, Eigen::Matrix3d::Zero(), J_inv;
  return jac;
}

Matrix6d SE3d::rightJacobian(const Vector6d& xi) { return leftJacobian(-xi); }

Matrix6d SE3d::rightJacobianInv(const Vector6d& xi) { return leftJacobianInv(-xi); }

}  // namespace vifusion
