#pragma once
// The paper's tracking problem (§IV-D, IV-E): at each frame, the previous state x0 and the current state
// x1 (state.hpp) are estimated jointly by Gauss-Newton over
//   - the dense photometric + ICP terms on x1's pose (GPU, through DenseTerms; already weighted by their
//     inverse measurement variances),
//   - the IMU error term e_IMU = x̂1(x0) ⊟ x1 with its information (imu_error.hpp),
//   - the marginalisation prior on x0: cost ½·Δᵀ·H*·Δ + b*ᵀ·Δ with Δ = x0 ⊟ x̄0, whose gradient
//     b* + H*·Δ is the paper's first-order correction (eq. 9); its Jacobian through ⊟ is applied too,
// coarse to fine over the dense terms' pyramid (a step that loses the dense terms' inliers is taken back and
// ends its level: EstimatorOptions::max_inlier_loss). Then x0 is marginalised by the Schur complement
// (eq. 8), H* = H11 − H10·H00⁻¹·H01, b* = b1 − H10·H00⁻¹·b0, taken at the solution (the gradient is
// predicted there from the last linear system), and x1 becomes the next frame's x0.
// Sign convention throughout: b = JᵀWr is the gradient, the step is δ = −H⁻¹·b.
//
// Unobservable directions, explicitly:
//  - q_I_W's rotation about gravity (I's z axis) is a pure gauge: nothing measures it. Its δg_z is never
//    estimated (the row and column are removed from every solve and from the prior), so it keeps the
//    value of the gravity initialisation.
//  - Global position and yaw of the camera: W is the first camera frame, fixed by the first state's tight
//    pose prior (EstimatorOptions::initial_pose_sigma); afterwards the dense terms observe the pose
//    against the map, which lives in W. When vision is unusable only the marginalised prior and the IMU
//    hold them, so their uncertainty grows as it should, and the map, which is not fused then, keeps
//    them fixed for when vision returns.
//  - In gyro mode velocity, accelerometer bias and q_I_W are held at their initial values (they are
//    unobservable without the accelerometer) and only the rotation and gyro-bias residuals are used,
//    with the marginal information of those six components.
// Vision failure: when the dense terms are unusable, the tracking-health test fails, or the dense solution
// is grossly inconsistent with the IMU and the prior (it raises their cost by more than
// EstimatorOptions::vision_gate_chi2 over their own optimum and moves the pose by more than the gate's
// minimum step: after seconds of dead reckoning the dense terms can converge metres away), the frame is
// solved from the IMU prediction with the IMU term and the prior only (gyro mode holds x1's position at
// the constant-velocity guess then): the IMU carries the state and the caller does not fuse.

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <span>

#include "vifusion/core/se3.hpp"
#include "vifusion/core/sensor_data.hpp"
#include "vifusion/core/state.hpp"
#include "vifusion/estimator/dense_pose_system.hpp"
#include "vifusion/estimator/estimator_options.hpp"
#include "vifusion/imu/imu_error.hpp"
#include "vifusion/imu/imu_options.hpp"
#include "vifusion/imu/preintegration.hpp"

namespace vifusion::estimator {

/// What the estimator needs from the dense RGB-D terms.
class DenseTerms {
 public:
  virtual ~DenseTerms() = default;
  /// Pyramid levels, 1..3 (level 0 is the finest).
  virtual int levels() const = 0;
  /// The terms' normal equations at `level` for the camera pose T_W_C, over x1's [δr, δα]
  /// (dense_pose_system.hpp). false when unusable (too few inliers, degenerate).
  virtual bool evaluate(int level, const SE3d& T_W_C, PoseSystem& system) = 0;
  /// The tracking-health test on the last level-0 evaluation: may the map trust this pose?
  virtual bool healthy() const = 0;
};

struct FrameSolve {
  bool vision_used = false;  ///< the dense terms are part of the solution (else IMU and prior only)
  int iterations = 0;        ///< Gauss-Newton iterations, including an inertial-only re-solve
  int reintegrations = 0;    ///< preintegrations redone at a moved gyro bias
  int backtracks = 0;        ///< pyramid levels ended by a step that lost inliers (EstimatorOptions::max_inlier_loss)
  /// e_IMUᵀ·W·e_IMU at the solution. Small when vision and IMU agree (both states absorb most of the
  /// IMU noise, so it is far below χ²(18)); a jump says the dense solution fights the IMU.
  double imu_chi2 = 0.0;
  /// How far the dense terms pulled (x0, x1) from the IMU-and-prior optimum: the rise of that cost
  /// [χ²]; 0 without a dense solution. Above EstimatorOptions::vision_gate_chi2 (with a step above the
  /// gate's minimum) the solution is refused.
  double vision_chi2 = 0.0;
  bool vision_rejected = false;  ///< the dense solution converged but failed that gate
  bool restarted = false;        ///< even the inertial-only system was singular: restarted at the IMU prediction
};

class TwoStateEstimator {
 public:
  static constexpr int kDim = 2 * kStateDim;
  using Matrix36d = Eigen::Matrix<double, kDim, kDim>;
  using Vector36d = Eigen::Matrix<double, kDim, 1>;

  /// @param T_S_C  camera → IMU (Kalibr's T_cam_imu is T_C_S)
  /// @throws vifusion::Error from the options' validation.
  TwoStateEstimator(const EstimatorOptions& options, const imu::ImuOptions& imu_options, const SE3d& T_S_C);

  /// Starts (or restarts) at a frame at t_ns with `x` as the state's mean: its pose with the tight
  /// initial pose prior (W's gauge), velocity, biases (Table I priors from the IMU options' noise) and
  /// gravity direction with the options' σ.
  void initialise(std::int64_t t_ns, const NavState& x);
  bool initialised() const { return initialised_; }
  /// Stops: initialised() is false until the next initialise() (the caller has no verified pose to restart from).
  void stop() { initialised_ = false; }

  /// Tracks the frame at t1_ns: preintegrates `samples` (must cover [t(), t1_ns] on the IMU clock),
  /// predicts x1, solves, marginalises x0. `dense` may be nullptr (no vision for this frame). On an IMU
  /// sample problem nothing changes and the issue is returned (the caller re-initialises, e.g. from the
  /// RGB-D-only pose). Allocates nothing.
  [[nodiscard]] std::optional<imu::ImuSampleIssue> track(std::int64_t t1_ns, std::span<const ImuSample> samples,
                                                         DenseTerms* dense, FrameSolve& summary);

  std::int64_t t_ns() const { return t_ns_; }
  /// The latest state (x1 after track(), the initial state after initialise()).
  const NavState& state() const { return x0_; }
  /// Marginal variances of the latest state's δx from the prior H* (0 for the held gauge/mode dims).
  Vector18d covarianceDiagonal() const;
  /// The prior on the latest state: information H*, gradient b* (at state()).
  const Matrix18d& priorInformation() const { return prior_H_; }
  const Vector18d& priorGradient() const { return prior_b_; }
  const EstimatorOptions& options() const { return options_; }

  /// Moves the latest state with the map when a loop closure deforms it (slam/loop_closure.hpp), by the rigid
  /// correction T_Wnew_Wold the deformation gives the camera: position and orientation in W move with it, the
  /// velocity (in I) turns with it, R_I = R_I_W·R·R_W_I, so the IMU's velocity relative to its body is kept,
  /// and q_I_W, the biases and the time stay (E_imu keeps R's tilt away from gravity, so R is a turn about
  /// it). The marginalisation prior is carried with the state: its linearisation point moves the same way,
  /// and since δr, δα (W) and δv (I) turn with R and R_I, H* → J·H*·Jᵀ and b* → J·b* with
  /// J = diag(R, R, R_I, I, I, I) (orthogonal), which leaves the prior's energy of every state unchanged.
  /// Between frames only (after track() or initialise()).
  void moveWithMap(const SE3d& T_Wnew_Wold);

 private:
  using Mask18 = Eigen::Matrix<double, kStateDim, 1>;  ///< 1 = estimated, 0 = held

  /// Builds H, b over [δx0, δx1] at the current x0_, x1_ with the optional dense system on x1's pose;
  /// dims of x1 outside `mask1` are held.
  void buildSystem(const PoseSystem* dense, const Mask18& mask1);
  /// Solves the built system and applies the step to x0_, x1_. false if singular or not finite.
  bool solveAndUpdate(Vector36d& step);
  /// The step of the built system (not applied). false if singular or not finite.
  bool solveStep(Vector36d& step);
  /// The IMU information in this mode (gyro: the marginal information of the rotation and gyro-bias rows).
  Matrix18d modeInformation(const Matrix18d& information) const;
  void marginalise(const Vector36d& last_step);
  /// Gauss-Newton over the dense terms, the IMU term and the prior, coarse to fine from the current x0_, x1_;
  /// a step that loses inliers is taken back and ends its level. false when the dense terms are unusable,
  /// a system is singular, or the tracking-health test fails.
  bool solveDense(DenseTerms& dense, Vector36d& step, FrameSolve& summary);
  /// The gross-inconsistency gate on the dense solution in x0_, x1_ (EstimatorOptions::vision_gate_chi2):
  /// true when refused, leaving the inertial-only solution from (x0_start, x1_start) in place; false
  /// restores the dense solution and its system. Fills summary.vision_chi2 / vision_rejected.
  bool refusedByGate(const NavState& x0_start, const NavState& x1_start, Vector36d& step, FrameSolve& summary);
  /// Solves the frame with the IMU term and the prior only, from (x0, x1) = the IMU prediction. false if
  /// the system is singular.
  bool solveInertialOnly(const NavState& x0_start, const NavState& x1_start, Vector36d& step, int& iterations,
                         int& reintegrations);
  /// The IMU term's χ² plus the prior's cost 2·(½ΔᵀH*Δ + b*ᵀΔ), at x0_, x1_.
  double inertialCost() const;
  void reintegrateIfNeeded(int& reintegrations);

  EstimatorOptions options_;
  imu::ImuPreintegrator preintegrator_;
  imu::ImuError imu_error_;
  Mask18 x0_estimated_;      ///< dims of x0 estimated in this mode (never δg_z)
  Mask18 x1_estimated_;      ///< dims of x1 estimated with vision
  Mask18 x1_inertial_only_;  ///< dims of x1 estimated without vision

  bool initialised_ = false;
  std::int64_t t_ns_ = 0;
  NavState x0_, x1_;
  Eigen::Vector3d last_translation_W_m_ = Eigen::Vector3d::Zero();  ///< r1 − r0 of the last frame (gyro mode's guess)
  Matrix18d prior_H_ = Matrix18d::Zero();
  Vector18d prior_b_ = Vector18d::Zero();
  NavState prior_x_;  ///< linearisation point of the prior (x̄0)

  std::span<const ImuSample> samples_;
  std::int64_t t1_ns_ = 0;
  imu::PreintegratedImu pre_;
  Matrix36d H_;
  Vector36d b_;
  Mask18 mask1_;  ///< dims of x1 estimated in the current solve
  Eigen::LDLT<Matrix36d> ldlt_;
};

}  // namespace vifusion::estimator
