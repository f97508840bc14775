#pragma once
// Reconstruction error as the paper reports it for ICL-NUIM: the mean distance of the map's points
// to the nearest true surface, after bringing the map into the ground truth's world with the
// trajectory alignment. The true surface is a distance function (the simulator's analytic scene).

#include <Eigen/Core>
#include <cstddef>
#include <functional>
#include <vector>

#include "vifusion/core/se3.hpp"

namespace vifusion::eval {

struct ReconstructionError {
  double mean_m = 0.0;
  double median_m = 0.0;
  double rms_m = 0.0;
  double within_1cm = 0.0;  ///< fraction of points closer than 1 cm to the true surface
  std::size_t points = 0;
};

/// @param points_est  map points in the estimate's world [m]
/// @param T_gt_est    alignment of the estimate onto the ground truth (AteResult::T_gt_est)
/// @param distance_m  unsigned distance from a ground-truth-world point to the true surface [m]
/// @throws vifusion::Error when there are no points.
ReconstructionError reconstructionError(const std::vector<Eigen::Vector3d>& points_est, const SE3d& T_gt_est,
                                        const std::function<double(const Eigen::Vector3d&)>& distance_m);

}  // namespace vifusion::eval
