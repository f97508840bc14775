#pragma once
// What every sensor source produces (live driver, dataset reader, simulator): timestamped RGB-D
// frames and IMU samples, plus the simulator's ground truth. Times are int64 ns on the host's
// CLOCK_MONOTONIC after clock mapping (datasets: their own time base, monotonic).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

#include "vifusion/core/image.hpp"

namespace vifusion {

/// One IMU reading in the IMU sensor frame S, as measured (biases and noise included).
struct ImuSample {
  int64_t t_ns = 0;
  Eigen::Vector3d gyro_rad_s = Eigen::Vector3d::Zero();  ///< angular rate of S w.r.t. inertial space, in S [rad/s]
  Eigen::Vector3d accel_mps2 = Eigen::Vector3d::Zero();  ///< specific force in S [m/s²] (≈ +9.81 up at rest)
};

/// One registered depth + colour frame. Depth is kept in the sensor's units so that nothing is
/// converted on the host; the GPU applies depth_scale_m.
struct RgbdFrame {
  int64_t t_ns = 0;          ///< mid-exposure time of the frame
  int64_t index = 0;         ///< position in the sequence (0, 1, 2, …)
  Image<uint16_t> depth;     ///< raw depth, 0 = invalid
  double depth_scale_m = 0;  ///< metres per depth unit (0.001 mm sensors, 1/5000 TUM and ICL-NUIM)
  Image<Rgb8> rgb;           ///< colour registered to depth, bytes R, G, B
};

/// The simulator's true state at an IMU sample: pose of S in the dataset world W, velocity, biases.
struct GroundTruthState {
  int64_t t_ns = 0;
  Eigen::Vector3d p_W_S = Eigen::Vector3d::Zero();             ///< position of S in W [m]
  Eigen::Quaterniond q_W_S = Eigen::Quaterniond::Identity();   ///< orientation of S in W (Hamilton)
  Eigen::Vector3d v_W_S = Eigen::Vector3d::Zero();             ///< velocity of S in W [m/s]
  Eigen::Vector3d b_g = Eigen::Vector3d::Zero();               ///< gyroscope bias [rad/s]
  Eigen::Vector3d b_a = Eigen::Vector3d::Zero();               ///< accelerometer bias [m/s²]
};

}  // namespace vifusion
