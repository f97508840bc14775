#pragma once
// Trajectory error metrics of the TUM RGB-D benchmark (algorithms.md §4.1–4.2):
// ATE as evaluate_ate.py, RPE as evaluate_rpe.py --fixed_delta --delta_unit s.

#include <cstddef>
#include <vector>

#include "vifusion/core/se3.hpp"
#include "vifusion/eval/trajectory_io.hpp"

namespace vifusion::eval {

struct AteResult {
  double rmse_m = 0.0;
  double mean_m = 0.0;
  double median_m = 0.0;
  double std_m = 0.0;  ///< Population standard deviation (numpy.std), as evaluate_ate.py --verbose.
  double min_m = 0.0;
  double max_m = 0.0;
  std::size_t pairs = 0;  ///< Associated (gt, est) pose pairs the statistics run over.
  SE3d T_gt_est;          ///< Rigid alignment applied to the estimate's positions.
  /// The pairs themselves, in time order (for plots): indices into gt and est, and each error [m].
  std::vector<std::size_t> gt_index;
  std::vector<std::size_t> est_index;
  std::vector<double> errors_m;
};

/// Absolute trajectory error: stamps associated as associate.py (|Δt| < max_difference_s, offset 0),
/// estimate positions aligned onto ground truth with alignRigid (no scale), e_i = ‖T_gt_est·p_est,i −
/// p_gt,i‖. Orientations are not used, as in evaluate_ate.py.
/// @throws vifusion::Error if fewer than 3 pairs associate (the alignment is then undetermined).
AteResult ate(const std::vector<StampedPose>& gt, const std::vector<StampedPose>& est, double max_difference_s = 0.02);

/// The same without alignment: the estimate's frame is taken to be T_gt_est in the ground truth's world, as
/// when a run relocalised into a saved map whose W is known there (its first camera's ground-truth pose). What
/// the errors then measure includes any offset of the whole trajectory, which ate() would align away.
AteResult ateInFrame(const std::vector<StampedPose>& gt, const std::vector<StampedPose>& est, const SE3d& T_gt_est,
                     double max_difference_s = 0.02);

struct RpeResult {
  double trans_rmse_m = 0.0;
  double trans_mean_m = 0.0;  ///< What evaluate_rpe.py prints without --verbose.
  double rot_rmse_deg = 0.0;
  double rot_mean_deg = 0.0;
  std::size_t pairs = 0;  ///< Pose pairs that survived the ground-truth matching.
};

/// Relative pose error over a fixed time step, evaluate_rpe.py --fixed_delta --delta <delta_s>
/// --delta_unit s (offset 0, scale 1). Pairs used:
///  - for every estimated pose i (stamps sorted), j = the estimated pose whose stamp is closest to
///    t_i + delta_s (evaluate_rpe.py's binary search, ported, so ties resolve the same way);
///  - the pair is dropped when j is the LAST estimated pose — a quirk of evaluate_rpe.py kept for
///    comparable numbers (it drops every i whose target lies at or past the end of the trajectory,
///    and also the one genuine pair ending on the last pose);
///  - t_i and t_j are each matched to the closest GT stamp; the pair is dropped if either match is
///    off by more than 2× the median GT period;
///  - unlike evaluate_rpe.py, all pairs are used: it subsamples 10,000 at random when there are more.
/// Error E = (P_j⁻¹P_i)⁻¹(Q_j⁻¹Q_i) with P estimate and Q GT; translational ‖t(E)‖ [m], rotational
/// arccos(clamp((tr R_E − 1)/2)) [deg].
/// @throws vifusion::Error if either trajectory has fewer than 2 poses or fewer than 2 pairs survive.
RpeResult rpe(const std::vector<StampedPose>& gt, const std::vector<StampedPose>& est, double delta_s = 1.0);

}  // namespace vifusion::eval
