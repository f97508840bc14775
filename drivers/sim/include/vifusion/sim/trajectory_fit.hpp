#pragma once
// Fitting the IMU-body spline to a camera trajectory (ICL-NUIM files, synthetic presets), as the paper did:
// "a smooth spline through every 10th pose" becomes ground truth, the IMU is simulated from it and images
// are rendered at the spline's camera poses T_W_C(t) = T_W_S(t)·T_S_C.
//
// Method: a quintic smoothing spline (Reinsch 1967), solved in the B-spline basis:
//  - samples: every `subsample`-th input pose plus the last one (so the spline covers the whole input), as
//    IMU poses T_W_S = T_W_C·T_S_C⁻¹;
//  - knots: uniform, by default one per subsampled pose. A quintic then has four more control points than
//    samples, so the data alone do not determine it; the penalty picks the smoothest near-interpolant;
//  - positions: linear least squares  Σ_i |p(t_i) − p_i|² + λ·Δt⁵·∫|p⃛(t)|² dt  (exact per-segment quadratic form,
//    Se3Spline::roughnessMatrix). Penalising the jerk makes the solution the natural quintic smoothing spline:
//    quadratic motion is never biased, and its end conditions do not ring between the first samples (a
//    penalty on control-point second differences, tried first, left 13 mm oscillations there);
//  - rotations: control rotations start at the sample rotations slerped to each control point's centre time,
//    then Gauss–Newton on  Σ_i |Log(R(t_i)ᵀ R_i)|² + λ·Δt⁵·(the same jerk energy of each segment's rotation-vector
//    increments d_j = Log(R_{j−1}ᵀ R_j)), with analytic Jacobians (Se3Spline::orientation) and right
//    perturbations of the control rotations. Converges in 3–6 iterations on ICL-NUIM and the presets.
// The default λ (w = λ·Δt⁵ = 10⁻⁶ s⁵ at 1/3 s knots) keeps the spline close to the ICL-NUIM samples (FitTolerance);
// the 30 Hz poses in between deviate more because the files jitter from frame to frame, which is what the
// subsampling removes. Smooth paths such as the presets are matched at every pose.

#include <cstdint>
#include <vector>

#include "vifusion/core/se3.hpp"
#include "vifusion/sim/se3_spline.hpp"
#include "vifusion/sim/stamped_pose.hpp"

namespace vifusion::sim {

struct TrajectoryFitOptions {
  int subsample = 10;                ///< use every n-th input pose (the paper: 10), ≥ 1
  std::int64_t knot_spacing_ns = 0;  ///< > 0: this spacing; 0: about the subsampled pose spacing, adjusted so
                                     ///< the last knot falls on the last input pose
  /// λ in the penalty λ·Δt⁵·∫|p⃛|² dt (Δt the knot spacing; the same for rotation), ≥ 0: relative to the data
  /// term it smooths alike at any spacing, so a denser fit follows faster motion as closely as the paper's follows
  /// ICL-NUIM. 2.43e-4 is w = 10⁻⁶ s⁵ at the paper's spacing (ten 30 Hz poses, Δt = 1/3 s).
  double smoothing = 2.43e-4;
  int max_iterations = 20;         ///< Gauss–Newton iterations on the rotations
  double convergence_rad = 1e-10;  ///< stop when the largest control-rotation update is below this [rad]
};

/// Deviation of the spline's camera poses from input camera poses.
struct FitResiduals {
  int count = 0;                       ///< poses compared
  double rms_position_mm = 0.0;        ///< RMS of |p_spline − p_input| [mm]
  double max_position_mm = 0.0;        ///< largest |p_spline − p_input| [mm]
  double rms_rotation_deg = 0.0;       ///< RMS of the angle of R_splineᵀ·R_input [deg]
  double max_rotation_deg = 0.0;       ///< largest such angle [deg]
  std::int64_t max_position_t_ns = 0;  ///< stamp of the pose with the largest position deviation
  std::int64_t max_rotation_t_ns = 0;  ///< stamp of the pose with the largest rotation deviation
};

/// How far a fit may miss the poses it was fitted through for its spline to be a ground truth: about the hand
/// jitter the paper's recipe (every 10th pose) leaves on ICL-NUIM's own files, whose residuals README.md gives
/// ("The synthetic benchmark and evaluation"). A fit that misses its own samples by more does not follow the
/// motion, and frames and IMU simulated along it would not show the path that was asked for.
struct FitTolerance {
  double max_position_mm = 2.0;   ///< [mm], > 0
  double max_rotation_deg = 0.1;  ///< [deg], > 0
};

/// Whether `residuals` (a fit's at_samples) stay within `tolerance`.
bool withinTolerance(const FitResiduals& residuals, const FitTolerance& tolerance);

struct TrajectoryFit {
  Se3Spline spline_W_S;            ///< the IMU body's trajectory: ground truth for everything downstream
  SE3d T_S_C;                      ///< camera → IMU (p_S = T_S_C·p_C), as given
  std::int64_t first_pose_ns = 0;  ///< stamp of the first input pose (= spline start)
  std::int64_t last_pose_ns = 0;   ///< stamp of the last input pose (≤ spline end)
  FitResiduals at_samples;         ///< at the subsampled poses the fit used
  FitResiduals at_all_poses;       ///< at every input pose (includes the jitter the fit smooths away)
  int iterations = 0;              ///< Gauss–Newton iterations run on the rotations

  /// T_W_C(t) = T_W_S(t)·T_S_C; throws vifusion::Error outside the spline's range.
  SE3d cameraPose(std::int64_t t_ns) const { return spline_W_S.pose(t_ns) * T_S_C; }
};

/// Fits the IMU-body spline to camera poses T_W_C.
/// @throws vifusion::Error if there are fewer than two poses, stamps do not strictly increase, an option is
///         out of range, or smoothing = 0 leaves more control points than samples.
TrajectoryFit fitTrajectory(const std::vector<StampedPose>& poses_W_C, const SE3d& T_S_C,
                            const TrajectoryFitOptions& options = {});

/// Deviation of fit.cameraPose(t) from the given camera poses (all must lie in the spline's range).
FitResiduals fitResiduals(const TrajectoryFit& fit, const std::vector<StampedPose>& poses_W_C);

}  // namespace vifusion::sim
