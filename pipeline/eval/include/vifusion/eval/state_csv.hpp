#pragma once
// The estimator's states.csv that `vifusion eval --states` compares with the simulator's
// groundtruth_states.csv (read by the datasets library, where the dataset layout lives).
// states.csv is written by `vifusion run` in the inertial modes, one row per frame, after a header:
//      t_ns, r_W_C_{x,y,z} [m], q_W_C_{x,y,z,w}, v_W_S_{x,y,z} [m/s], b_g_{x,y,z} [rad/s],
//      b_a_{x,y,z} [m/s²], g_W_{x,y,z}, q_I_W_{x,y,z,w}, var_<δx component> (18: the marginal variances
//      of state.hpp's δx = [δr, δα, δv, δb_g, δb_a, δg], SI units squared; 0 for dims not estimated).
// t_ns is the frame's camera time. Velocities are in the map world W (the state's v_I_S rotated by its
// own q_I_W), biases in the IMU frame S, g_W the estimated gravity direction in W (unit length; the
// reader accepts any length). The reader finds its columns by header name and ignores the others.

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "vifusion/core/state.hpp"

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

/// One frame of the estimator.
struct StateRecord {
  int64_t t_ns = 0;
  NavState x;
  Vector18d variance = Vector18d::Zero();  ///< marginal variances of δx
};

/// Writes states.csv in the layout above with 17 significant digits, atomically (core/atomic_file.hpp).
/// @throws vifusion::Error if the file cannot be written.
void writeEstimatedStates(const std::filesystem::path& path, std::span<const StateRecord> records);

}  // namespace vifusion::eval
