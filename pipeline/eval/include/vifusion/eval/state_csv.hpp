#pragma once
// The estimator's states.csv that `vifusion eval --states` compares with the simulator's
// groundtruth_states.csv (read by the datasets library, where the dataset layout lives).
// states.csv is written by `vifusion run`, one row per frame; columns found by header name:
//      t_ns, v_W_S_{x,y,z}, b_g_{x,y,z}, b_a_{x,y,z}, g_W_{x,y,z} (others, e.g. poses and
//      covariance diagonals, are ignored here).
// Velocities are in the dataset/map world W [m/s], biases in the IMU frame S, g_W the estimated
// gravity direction in W (any length).

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <vector>


namespace vifusion::eval {

struct EstimatedState {
  int64_t t_ns = 0;
  Eigen::Vector3d v_W_S = Eigen::Vector3d::Zero();  ///< velocity of S in the estimate's world [m/s]
  Eigen::Vector3d b_g = Eigen::Vector3d::Zero();    ///< gyroscope bias [rad/s]
  Eigen::Vector3d b_a = Eigen::Vector3d::Zero();    ///< accelerometer bias [m/s²]
  Eigen::Vector3d g_W = Eigen::Vector3d::Zero();    ///< gravity direction in the estimate's world
};

/// @throws vifusion::Error naming file, line and column on a missing column, a non-number,
/// non-finite values or time that does not strictly increase.
std::vector<EstimatedState> readEstimatedStates(const std::filesystem::path& path);

}  // namespace vifusion::eval
