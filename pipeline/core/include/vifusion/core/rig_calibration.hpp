#pragma once
// Everything needed to interpret a camera + IMU rig's data: intrinsics, depth units and bias, the
// camera-to-IMU transform, the camera-IMU time offset, IMU noise and gravity in the data's world.

#include <Eigen/Core>
#include <cstdint>
#include <optional>

#include "vifusion/core/camera_noise_model.hpp"
#include "vifusion/core/imu_noise.hpp"
#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/core/se3.hpp"

namespace vifusion {

/// Largest |RigCalibration::inverse_depth_bias_per_m| accepted [1/m]: a 10 % depth error at 1 m, far
/// beyond any working sensor, so a larger value is a typo (a bias in 1/mm, a depth in place of 1/z).
inline constexpr double kMaxInverseDepthBias_per_m = 0.1;

/// A depth camera apart from the colour camera: the ZR300 measures depth with its IR stereo pair, a few
/// centimetres from the colour imager, so its depth pixels and colour pixels with the same (u, v) see
/// different points until preprocessing registers depth to colour (preprocess/depth_registration.hpp).
struct DepthCameraCalibration {
  PinholeCamera camera;  ///< intrinsics and size of the raw depth images (rectified by the device)
  SE3d T_C_D;            ///< depth → colour camera: p_C = T_C_D · p_D [m]
};

struct RigCalibration {
  PinholeCamera camera;  ///< the colour camera C; the pipeline works in its pixels
  /// Set when depth images come from their own camera (live ZR300, its recordings); unset when they are
  /// already in the colour camera's pixels (datasets, the simulator). Frames then carry depth at
  /// depth_camera->camera's size.
  std::optional<DepthCameraCalibration> depth_camera;
  double depth_scale_m = 1.0 / 5000.0;  ///< metres per raw depth unit in the data
  /// Systematic depth error as an offset of inverse depth: the sensor reports 1/z_raw = 1/z + b [1/m].
  /// Structured-light and stereo sensors measure disparity ∝ 1/z, so a disparity offset is their
  /// dominant depth bias (Herrera et al., PAMI 2012). Its effect on a trajectory is twice the depth
  /// error: moving from z₁ to z₂ reads as a move of (z₂ − z₁)(1 − b(z₁ + z₂)), so b = 1.4e-3 (the
  /// simulated Kinect, scene/sensor_noise.hpp) shrinks motion at 2–4 m by 0.6–1.1 %. 0: unbiased.
  double inverse_depth_bias_per_m = 0.0;
  /// The camera's depth and intensity noise as measured by `vifusion calib noise`; unset until measured.
  std::optional<CameraNoiseModel> noise;
  /// Camera → IMU: p_S = T_S_C · p_C. Kalibr's `T_cam_imu` is T_C_S, the inverse of this.
  SE3d T_S_C;
  /// Kalibr `timeshift_cam_imu`: t_imu = t_cam + time_shift_cam_imu_ns.
  int64_t time_shift_cam_imu_ns = 0;
  ImuNoiseParams imu;
  /// Gravity in the dataset's world frame [m/s²]; y-up worlds (ICL-NUIM) have (0, −9.81, 0).
  Eigen::Vector3d g_W = Eigen::Vector3d(0.0, -9.81, 0.0);
};

}  // namespace vifusion
