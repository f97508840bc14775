#pragma once
// The camera's tilt against gravity, frame by frame and with no alignment: the angle between "down" as the
// estimate sees it from the camera, R_W_C,est^T·g_W,est (the estimator's gravity in its own world), and as the
// truth does, R_G_C^T·g_G [deg]. A loop closure that tilts part of the map tilts every camera pose tracked in it
// against the estimator's gravity (which a deformation leaves as it was, two_state_estimator.hpp), so this is
// the map's gravity tilt as the robot meets it: issue 16's "tilt after closures" with and without E_imu. It also
// holds the estimator's own gravity error and the camera's roll and pitch error; an open-loop run gives that floor.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "vifusion/eval/state_csv.hpp"
#include "vifusion/eval/trajectory_io.hpp"

namespace vifusion::eval {

struct CameraTiltSample {
  std::int64_t t_ns = 0;  ///< the estimated pose's stamp
  double tilt_deg = 0.0;  ///< angle between R_W_C,est^T·g_W,est and R_G_C^T·g_G, in [0, 180]
};

struct CameraTilt {
  std::vector<CameraTiltSample> series;
  double rms_deg = 0.0;
  double max_deg = 0.0;
  double final_deg = 0.0;
};

/// One sample per associated pose pair (gt_index[i], est_index[i], as eval::ate returns them) whose estimated
/// pose has a state with the same stamp to within `max_difference_ns` (the nearest one). g_gt_W: gravity in
/// the ground truth's world (any length > 0).
/// @throws vifusion::Error when no pair has a state, or g_gt_W or a state's g_W is zero or not finite.
CameraTilt cameraTilt(const std::vector<StampedPose>& gt, const std::vector<StampedPose>& est,
                      const std::vector<std::size_t>& gt_index, const std::vector<std::size_t>& est_index,
                      const std::vector<EstimatedState>& states, const Eigen::Vector3d& g_gt_W,
                      std::int64_t max_difference_ns);

}  // namespace vifusion::eval
