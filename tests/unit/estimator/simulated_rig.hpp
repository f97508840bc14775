#pragma once
// A simulated RGB-D-inertial rig for the estimator's tests: a preset path of drivers/sim, its IMU with
// Table I noise and random biases (seeded), 30 Hz frame times off the IMU grid, the true state at any
// time, and a stand-in for the dense terms that measures the true camera pose with Gaussian noise.

#include <Eigen/Geometry>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "vifusion/core/se3.hpp"
#include "vifusion/core/sensor_data.hpp"
#include "vifusion/core/state.hpp"
#include "vifusion/estimator/two_state_estimator.hpp"
#include "vifusion/sim/imu_simulator.hpp"
#include "vifusion/sim/normal_rng.hpp"
#include "vifusion/sim/trajectory_fit.hpp"

namespace vifusion::estimator::test {

/// A rig like a real one: 4.5 cm lever arm, 3° misalignment.
SE3d rigT_S_C();

/// The presets' world is y-up; I is z-up. R_x(90°) takes W's y onto I's z, and a yaw about I's z (the
/// gauge) keeps tests from passing by accident at yaw 0.
Eigen::Quaterniond trueQ_I_W();

struct SimulatedRig {
  SE3d T_S_C;
  sim::TrajectoryFit fit;
  sim::ImuSimResult imu;
  std::vector<std::int64_t> frame_times_ns;  ///< 30 Hz, 12.3 ms off the IMU grid

  /// The preset's whole path; the IMU with Table I noise and random biases from `seed`, or (realistic =
  /// false) exact readings.
  SimulatedRig(const std::string& preset, std::uint64_t seed, bool realistic = true);
  /// The true state at t_ns (biases of the nearest IMU sample, the ones in effect).
  NavState trueState(std::int64_t t_ns) const;
  /// The state an estimator starts from at the first frame: true pose (W is defined by it), zero
  /// velocity (presets start at rest) and biases, gravity from the first 200 ms of accelerometer.
  NavState initialState() const;
};

/// A pose measurement standing in for the dense terms: the true camera pose perturbed once per frame by
/// N(0, σ²) in [δr, δα], evaluated as residual r = [r − r_m; log(q·q_mᵀ)] with Jacobian diag(I, J_l⁻¹).
class SimulatedVision : public DenseTerms {
 public:
  SimulatedVision(double sigma_m, double sigma_rad, std::uint64_t seed);
  /// Draws the measurement of the pose T_W_C for the next frame.
  void observe(const SE3d& T_W_C_true);
  void setHealthy(bool healthy) { healthy_ = healthy; }
  /// Makes the terms' Gauss-Newton steps `factor` times too long (their information divided by it) and
  /// their inliers fall off with the distance from the measurement (σ 5 cm): a solve that overshoots
  /// out of its basin. 1: exact steps, constant inliers.
  void setOvershoot(double factor) { overshoot_ = factor; }

  int levels() const override { return 3; }
  bool evaluate(int level, const SE3d& T_W_C, PoseSystem& system) override;
  bool healthy() const override { return healthy_; }
  int evaluations() const { return evaluations_; }

 private:
  double sigma_m_, sigma_rad_;
  sim::NormalRng rng_;
  SE3d measured_T_W_C_;
  bool healthy_ = true;
  double overshoot_ = 1.0;
  int evaluations_ = 0;
};

}  // namespace vifusion::estimator::test
