#include "tracker_dense_terms.hpp"

#include "vifusion/tracking/icp_degeneracy.hpp"

namespace vifusion::slam {

bool TrackerDenseTerms::evaluate(int level, const SE3d& T_W_C, estimator::PoseSystem& system) {
  TrackingResult statistics;
  NormalEquations6 equations = tracker_.evaluate(level, T_W_ref_.inverse() * T_W_C, statistics);
  if (level == 0) statistics_ = statistics;
  // Six rows make any pose direction determinable; fewer is an empty view (or none at all).
  if (!(equations.inliers >= 6.0) || !equations.H.allFinite() || !equations.b.allFinite()) return false;
  tracking::removeUnconstrainedIcpDirections(tracker_.icpEquations(level), options_.icp_min_constraint_share,
                                             equations);
  system = estimator::toStatePose(options_.information_scale * equations.H, options_.information_scale * equations.b,
                                  T_W_ref_, T_W_C);
  system.inliers = equations.inliers;
  return true;
}

}  // namespace vifusion::slam
