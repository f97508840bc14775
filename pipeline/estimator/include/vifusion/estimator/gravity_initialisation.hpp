#pragma once
// The first gravity direction q_I_W from the accelerometer. At rest the specific force is gravity's
// reaction, +g up: f_S = R_S_I·(0, 0, g). Rotating the mean reading into W (through the first camera
// pose and T_S_C) gives "up" in W; q_I_W is the smallest rotation taking it to I's z axis. Its rotation
// about that axis (yaw) is free — the gauge the estimator holds fixed (two_state_estimator.hpp).

#include <Eigen/Geometry>
#include <optional>
#include <span>

#include "vifusion/core/se3.hpp"
#include "vifusion/core/sensor_data.hpp"

namespace vifusion::estimator {

struct GravityInitialisation {
  Eigen::Quaterniond q_I_W = Eigen::Quaterniond::Identity();
  Eigen::Vector3d mean_specific_force_S_mps2 = Eigen::Vector3d::Zero();  ///< in S, bias removed [m/s²]
  int samples = 0;
};

/// Averages the accelerometer over `samples` (the caller picks the window) less the known bias accel_bias_S
/// [m/s², in S] (the calibration's static bias: Table I's 0.29 m/s² for the ZR300 tilts "up" by 27 mrad otherwise).
/// nullopt when the span is empty or its mean is too short to have a direction (< 1 m/s²: free fall, or not an
/// accelerometer).
std::optional<GravityInitialisation> initialGravity(std::span<const ImuSample> samples, const SE3d& T_W_C,
                                                    const SE3d& T_S_C,
                                                    const Eigen::Vector3d& accel_bias_S = Eigen::Vector3d::Zero());

}  // namespace vifusion::estimator
