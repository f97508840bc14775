#pragma once
// Everything needed to interpret a camera + IMU rig's data: intrinsics, depth units, the
// camera-to-IMU transform, the camera-IMU time offset, IMU noise and gravity in the data's world.

#include <Eigen/Core>
#include <cstdint>

#include "vifusion/core/imu_noise.hpp"
#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/core/se3.hpp"

namespace vifusion {

struct RigCalibration {
  PinholeCamera camera;
  double depth_scale_m = 1.0 / 5000.0;  ///< metres per raw depth unit in the data
  /// Camera → IMU: p_S = T_S_C · p_C. Kalibr's `T_cam_imu` is T_C_S, the inverse of this.
  SE3d T_S_C;
  /// Kalibr `timeshift_cam_imu`: t_imu = t_cam + time_shift_cam_imu_ns.
  int64_t time_shift_cam_imu_ns = 0;
  ImuNoiseParams imu;
  /// Gravity in the dataset's world frame [m/s²]; y-up worlds (ICL-NUIM) have (0, −9.81, 0).
  Eigen::Vector3d g_W = Eigen::Vector3d(0.0, -9.81, 0.0);
};

}  // namespace vifusion
