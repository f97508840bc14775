#pragma once
// Camera placement for presets, tests and benchmarks: a vision-convention camera (x right, y down,
// z forward) at eye_W looking at target_W, upright with respect to up_W (world y-up by default).

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "vifusion/core/se3.hpp"

namespace vifusion::scene {

/// T_W_C of the camera; the view direction must not be parallel to up_W.
inline SE3d lookAt(const Eigen::Vector3d& eye_W, const Eigen::Vector3d& target_W,
                   const Eigen::Vector3d& up_W = Eigen::Vector3d::UnitY()) {
  const Eigen::Vector3d z_W = (target_W - eye_W).normalized();
  const Eigen::Vector3d x_W = z_W.cross(up_W).normalized();  // right
  const Eigen::Vector3d y_W = z_W.cross(x_W);                // down
  Eigen::Matrix3d R_W_C;
  R_W_C << x_W, y_W, z_W;
  return SE3d(Eigen::Quaterniond(R_W_C), eye_W);
}

}  // namespace vifusion::scene
