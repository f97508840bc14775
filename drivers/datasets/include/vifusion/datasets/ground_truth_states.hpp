#pragma once
// groundtruth_states.csv of our dataset directories (DESIGN §5): the simulator's true IMU state at
// every IMU sample, one row each, after a header naming the columns:
//   #t_ns,p_W_S_x,p_W_S_y,p_W_S_z,q_W_S_x,q_W_S_y,q_W_S_z,q_W_S_w,v_W_S_x,v_W_S_y,v_W_S_z,b_g_x,b_g_y,b_g_z,b_a_x,b_a_y,b_a_z
// p [m], q Hamilton x y z w (T_W_S's rotation), v [m/s], b_g [rad/s], b_a [m/s²]; W is the dataset world.

#include <filesystem>
#include <span>
#include <vector>

#include "vifusion/core/sensor_data.hpp"

namespace vifusion::datasets {

/// Reads groundtruth_states.csv. The header is required and must name the 17 columns above in that
/// order (a quaternion written w-first would otherwise be read as a different rotation).
/// @throws vifusion::Error naming file and line: bad header, missing column, non-finite value,
/// quaternion norm off 1 by more than 1e-3, timestamp not strictly increasing.
std::vector<GroundTruthState> readGroundTruthStates(const std::filesystem::path& path);

/// Writes states in that layout with 17 significant digits: readGroundTruthStates returns every value
/// bit-exact except q_W_S, which it re-normalises (a change of at most a few ulp).
/// @throws vifusion::Error if the file cannot be written.
void writeGroundTruthStates(const std::filesystem::path& path, std::span<const GroundTruthState> states);

}  // namespace vifusion::datasets
