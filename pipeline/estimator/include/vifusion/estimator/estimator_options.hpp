#pragma once
// Options of the two-state RGB-D-inertial estimator (two_state_estimator.hpp), with defaults that every
// sequence uses (the paper insists on one parameter set) and validation naming the bad field.

#include <array>
#include <cstdint>
#include <numbers>
#include <string>

#include "vifusion/core/step_convergence.hpp"

namespace vifusion::estimator {

/// The paper's ablations besides RGB-D only (which does not use this estimator).
enum class InertialMode {
  kRgbdInertial,  ///< every IMU residual: pose, velocity, biases, gravity direction estimated
  kGyro,          ///< accelerometer ignored: only the rotation and gyro-bias residuals; v, b_a, q_I_W held
};

/// "rgbdi" or "gyro"; throws vifusion::Error naming the valid values otherwise.
InertialMode inertialModeFromName(const std::string& name);
const char* inertialModeName(InertialMode mode);

struct EstimatorOptions {
  InertialMode mode = InertialMode::kRgbdInertial;
  /// Gauss-Newton iterations per pyramid level, finest first; the slam library copies the dense
  /// tracker's (10, 5, 4) so both modes run the same schedule. Levels beyond the dense terms' are unused.
  std::array<int, 3> iterations = {10, 5, 4};
  /// A level stops early when x1's pose step is within the dense terms' uncertainty: its squared Mahalanobis
  /// length under their information below this (core/step_convergence.hpp; the slam library copies the dense
  /// tracker's). > 0.
  double converged_step_chi2 = kChi2SixDofQuantile001;
  /// A Gauss-Newton step after which the dense terms keep fewer than (1 − this) of their inliers is taken
  /// back and its pyramid level ends there: the solve is leaving the dense terms' basin. white_wall at
  /// 640×480 on the way back from the wall (0.28 m of drift): level 0 walked 2.4 m along the wall in seven
  /// steps while its inliers fell 268 k → 263 k → 254 k → 228 k → … → 0, and the frame was lost. In (0, 1];
  /// 1 turns the check off.
  double max_inlier_loss = 0.01;
  /// Gauss-Newton iterations of a frame solved without the dense terms (IMU + prior only: nearly
  /// linear, so few are needed). ≥ 1.
  int inertial_only_iterations = 3;
  /// The gross-inconsistency gate (rgbdi mode): a frame's dense solution is refused (the IMU and the prior
  /// carry the frame, which is not fused) when it raises the IMU-and-prior cost above their own optimum by
  /// more than this χ² (FrameSolve::vision_chi2) AND moves x1's pose from their solution by more than the
  /// step below. Measured at 320×240: living_room_0's 600 frames ≤ 6.3; white_wall's dense terms converging
  /// 1.8–2.1 m off after the wall 127 and 182. > 0; +inf turns the gate off.
  double vision_gate_chi2 = 40.0;
  /// The step a refused solution must also exceed [m, rad], because after fast motion the estimator can be
  /// over-confident: on quick_rotation (640×480) correct pulls of 30–140 mm back onto the map scored χ²
  /// 40–257, at white_wall's turn correct 0.3° yaw pulls up to 149, and its relock after the wall pulled
  /// 0.28 m with χ² 96–134; the wrong basin it guards against was 1.8–2.1 m away. > 0.
  double vision_gate_min_step_m = 0.5;
  double vision_gate_min_step_rad = 5.0 * std::numbers::pi / 180.0;

  /// Prior of the first state. W is the first camera frame (DESIGN §3), so its pose is known up to
  /// this σ [m, rad]: it fixes the gauge of global position and yaw.
  double initial_pose_sigma = 1e-6;
  /// 1σ of the first velocity [m/s]. The first frames' poses and the IMU determine it (a joint solve of
  /// two poses and the preintegrated Δp gives v0); the prior only keeps the first system regular.
  double initial_velocity_sigma_mps = 1.0;
  /// 1σ of the first gravity direction [rad] about the two horizontal axes of I, after its initialisation
  /// from the mean specific force (an average over motion whose acceleration is ≤ 0.5 m/s² is off by ≤ 3°).
  double initial_gravity_sigma_rad = 0.05;
  /// Window of accelerometer samples averaged for the first gravity direction, ending at the first frame
  /// [ns]. Longer averages out more noise; shorter sees less of the start's motion.
  std::int64_t gravity_window_ns = 200'000'000;

  /// Throws vifusion::Error naming the first field out of range.
  void validate() const;
};

}  // namespace vifusion::estimator
