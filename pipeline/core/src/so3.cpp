#include "vifusion/core/so3.hpp"

#include <cmath>

#include "rotation_series.hpp"

namespace vifusion {

Eigen::Matrix3d hat(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(),  //
      v.z(), 0.0, -v.x(),   //
      -v.y(), v.x(), 0.0;
  return m;
}

Eigen::Quaterniond expSO3(const Eigen::Vector3d& omega) {
  const double theta = omega.norm();
  const Eigen::Vector3d xyz = detail::halfSinOverAngle(theta) * omega;
  return Eigen::Quaterniond(std::cos(0.5 * theta), xyz.x(), xyz.y(), xyz.z());
}

Eigen::Vector3d logSO3(const Eigen::Quaterniond& q) {
  // Pick the representative with w ≥ 0 so the angle 2·atan2(|v|, w) lies in [0, π]; atan2 stays
  // well conditioned at both ends (unlike acos(w) near 0 or asin(|v|) near π).
  const double sign = q.w() < 0.0 ? -1.0 : 1.0;
  const double w = sign * q.w();
  const Eigen::Vector3d v = sign * q.vec();
  const double n = v.norm();
  if (n < 1e-6 * w) {
    // 2·atan(n/w)/n = (2/w)(1 − x²/3 + …), x = n/w < 1e-6: the next term is below 1e-24.
    const double x2 = (n * n) / (w * w);
    return (2.0 / w) * (1.0 - x2 / 3.0) * v;
  }
  return (2.0 * std::atan2(n, w) / n) * v;
}

Eigen::Matrix3d leftJacobianSO3(const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  const Eigen::Matrix3d Phi = hat(phi);
  return Eigen::Matrix3d::Identity() + detail::oneMinusCosOverAngleSq(theta) * Phi +
         detail::angleMinusSinOverAngleCubed(theta) * Phi * Phi;
}

Eigen::Matrix3d leftJacobianInvSO3(const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  const Eigen::Matrix3d Phi = hat(phi);
  return Eigen::Matrix3d::Identity() - 0.5 * Phi + detail::inverseJacobianCoefficient(theta) * Phi * Phi;
}

Eigen::Matrix3d rightJacobianSO3(const Eigen::Vector3d& phi) { return leftJacobianSO3(-phi); }

Eigen::Matrix3d rightJacobianInvSO3(const Eigen::Vector3d& phi) { return leftJacobianInvSO3(-phi); }

}  // namespace vifusion
