#pragma once
// Errors of the estimated velocity, IMU biases and gravity direction against the simulator's
// ground truth (the paper's Fig. 3). The estimate lives in its own world (the first camera frame),
// so velocities and gravity are rotated by an alignment R_gt_est first (`vifusion eval` uses the
// alignment of the associated poses, eval::alignPoses); biases live in the
// IMU frame and compare directly.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "vifusion/core/sensor_data.hpp"
#include "vifusion/eval/state_csv.hpp"

namespace vifusion::eval {

struct StateErrorSample {
  int64_t t_ns = 0;
  double velocity_mps = 0.0;     ///< ‖R_gt_est·v_est − v_gt‖ [m/s]
  double gyro_bias_rad_s = 0.0;  ///< ‖b_g,est − b_g,gt‖ [rad/s]
  double accel_bias_mps2 = 0.0;  ///< ‖b_a,est − b_a,gt‖ [m/s²]
  double gravity_deg = 0.0;      ///< angle between R_gt_est·g_est and g_gt [deg]
};

struct StateErrors {
  std::vector<StateErrorSample> series;  ///< one per estimated state inside the ground truth's time span
  double velocity_rms_mps = 0.0;
  double velocity_rms_after_5s_mps = 0.0;   ///< from 5 s after the first estimate (NaN if shorter)
  double gyro_bias_max_after_15s = 0.0;     ///< [rad/s] (NaN if shorter than 15 s)
  double accel_bias_max_after_15s = 0.0;    ///< [m/s²] (NaN if shorter than 15 s)
  double gyro_bias_final_rad_s = 0.0;
  double accel_bias_final_mps2 = 0.0;
  double gravity_rms_deg = 0.0;
  double gravity_final_deg = 0.0;
};

/// Ground truth is linearly interpolated to each estimate's time. `g_gt_W` is gravity in the
/// ground truth's world (e.g. (0, −9.81, 0) for y-up datasets).
/// @throws vifusion::Error when no estimate falls inside the ground truth's time span.
StateErrors stateErrors(const std::vector<GroundTruthState>& gt, const std::vector<EstimatedState>& est,
                        const Eigen::Matrix3d& R_gt_est, const Eigen::Vector3d& g_gt_W);

}  // namespace vifusion::eval
