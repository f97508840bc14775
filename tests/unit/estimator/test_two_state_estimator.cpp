// The two-state estimator on simulated IMU data (Table I noise, random biases) with a simulated pose
// measurement in place of the dense terms: it must find velocity, biases and gravity to the accuracy the
// issue asks of the full system, carry the state through a vision outage, run the gyro-only ablation,
// keep the gauge fixed and refuse broken IMU data without touching the state.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <random>
#include <vector>

#include "simulated_rig.hpp"
#include "vifusion/core/so3.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/imu/sample_window.hpp"

namespace vifusion::estimator {
namespace {

using test::SimulatedRig;
using test::SimulatedVision;

struct FrameErrors {
  std::int64_t t_ns = 0;
  double position_m = 0.0;
  double rotation_rad = 0.0;
  double velocity_mps = 0.0;  ///< compared in W: each side's own q_I_W takes v_I back to W
  double gyro_bias_rad_s = 0.0;
  double accel_bias_mps2 = 0.0;
  double gravity_deg = 0.0;
  bool vision_used = false;
  double imu_chi2 = 0.0;
};

Eigen::Vector3d velocityInW(const NavState& x) { return x.q_I_W.conjugate() * x.v_I_S; }
Eigen::Vector3d gravityInW(const NavState& x) { return x.q_I_W.conjugate() * Eigen::Vector3d(0.0, 0.0, -1.0); }

FrameErrors errorsOf(const NavState& est, const NavState& truth) {
  FrameErrors e;
  e.position_m = (est.r_W_C - truth.r_W_C).norm();
  e.rotation_rad = logSO3(est.q_W_C * truth.q_W_C.conjugate()).norm();
  e.velocity_mps = (velocityInW(est) - velocityInW(truth)).norm();
  e.gyro_bias_rad_s = (est.b_g - truth.b_g).norm();
  e.accel_bias_mps2 = (est.b_a - truth.b_a).norm();
  const Eigen::Vector3d a = gravityInW(est), b = gravityInW(truth);
  e.gravity_deg = std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / std::numbers::pi;
  return e;
}

/// Runs the estimator over the rig's frames; `vision_at(t_s)` says whether vision is healthy then.
std::vector<FrameErrors> run(
    const SimulatedRig& rig, const EstimatorOptions& options, SimulatedVision& vision,
    const std::function<bool(double)>& vision_at = [](double) { return true; }) {
  TwoStateEstimator estimator(options, imu::ImuOptions{}, rig.T_S_C);
  estimator.initialise(rig.frame_times_ns.front(), rig.initialState());
  std::vector<FrameErrors> errors;
  for (std::size_t k = 1; k < rig.frame_times_ns.size(); ++k) {
    const std::int64_t t_ns = rig.frame_times_ns[k];
    const NavState truth = rig.trueState(t_ns);
    vision.observe(SE3d(truth.q_W_C, truth.r_W_C));
    vision.setHealthy(vision_at(nsToSeconds(t_ns - rig.frame_times_ns.front())));
    FrameSolve solve;
    const auto issue =
        estimator.track(t_ns, imu::bracketingSamples(rig.imu.samples, estimator.t_ns(), t_ns), &vision, solve);
    if (issue) ADD_FAILURE() << issue->message();
    FrameErrors e = errorsOf(estimator.state(), truth);
    e.t_ns = t_ns - rig.frame_times_ns.front();
    e.vision_used = solve.vision_used;
    e.imu_chi2 = solve.imu_chi2;
    errors.push_back(e);
  }
  return errors;
}

/// Largest error of a kind from t_from_s on, and the RMS.
struct Summary {
  double max = 0.0, rms = 0.0;
};
Summary summarise(const std::vector<FrameErrors>& errors, double t_from_s, double FrameErrors::*field) {
  Summary s;
  int n = 0;
  for (const FrameErrors& e : errors) {
    if (nsToSeconds(e.t_ns) < t_from_s) continue;
    s.max = std::max(s.max, e.*field);
    s.rms += (e.*field) * (e.*field);
    ++n;
  }
  s.rms = n > 0 ? std::sqrt(s.rms / n) : 0.0;
  return s;
}

TEST(TwoStateEstimator, FindsVelocityBiasesAndGravityOnTheFastPreset) {
  // 20 s hand-held motion (1.9 m/s, 3 rad/s peaks); the pose measurement is as good as dense RGB-D
  // tracking on the synthetic sequences (2 mm, 0.1°). The issue's LR0 acceptance figures must hold:
  // velocity ≤ 2 cm/s RMS after 5 s, gyro bias ≤ 2e-3 rad/s and accelerometer bias ≤ 0.05 m/s² after 15 s,
  // gravity ≤ 0.5°.
  const SimulatedRig rig("fast", 11);
  SimulatedVision vision(0.002, 0.1 * std::numbers::pi / 180.0, 12);
  const std::vector<FrameErrors> errors = run(rig, EstimatorOptions{}, vision);
  const Summary velocity = summarise(errors, 5.0, &FrameErrors::velocity_mps);
  const Summary gyro = summarise(errors, 15.0, &FrameErrors::gyro_bias_rad_s);
  const Summary accel = summarise(errors, 15.0, &FrameErrors::accel_bias_mps2);
  const Summary gravity = summarise(errors, 5.0, &FrameErrors::gravity_deg);
  const Summary position = summarise(errors, 0.0, &FrameErrors::position_m);
  const Summary chi2 = summarise(errors, 1.0, &FrameErrors::imu_chi2);
  std::printf(
      "  velocity RMS after 5 s %.4f m/s | b_g max after 15 s %.2e rad/s | b_a max after 15 s %.4f m/s² |"
      " gravity max after 5 s %.3f° | position RMS %.2f mm | IMU χ² RMS %.1f\n",
      velocity.rms, gyro.max, accel.max, gravity.max, position.rms * 1e3, chi2.rms);
  EXPECT_EQ(errors.size(), rig.frame_times_ns.size() - 1);
  for (const FrameErrors& e : errors) ASSERT_TRUE(e.vision_used);
  EXPECT_LT(velocity.rms, 0.02);
  EXPECT_LT(gyro.max, 2e-3);
  EXPECT_LT(accel.max, 0.05);
  EXPECT_LT(gravity.max, 0.5);
  // Fusing the IMU smooths the measurement noise (2 mm per axis, 3.5 mm in 3D).
  EXPECT_LT(position.rms, 0.0035);
}

TEST(TwoStateEstimator, ImuCarriesTheStateThroughAVisionOutage) {
  // Vision unhealthy from 10 s to 11 s: the frames are solved from the IMU and the prior alone, the
  // position may drift by what the estimated biases, velocity and gravity leave (≪ the 1.9 m/s motion:
  // 1.9 m travelled), and vision takes over again as soon as it returns.
  const SimulatedRig rig("fast", 21);
  SimulatedVision vision(0.002, 0.1 * std::numbers::pi / 180.0, 22);
  const auto outage = [](double t_s) { return t_s >= 10.0 && t_s < 11.0; };
  const std::vector<FrameErrors> errors =
      run(rig, EstimatorOptions{}, vision, [&](double t_s) { return !outage(t_s); });
  double worst_in_outage_m = 0.0, worst_after_m = 0.0;
  int outage_frames = 0;
  for (const FrameErrors& e : errors) {
    const double t_s = nsToSeconds(e.t_ns);
    EXPECT_EQ(e.vision_used, !outage(t_s)) << "t = " << t_s << " s";
    if (outage(t_s)) {
      ++outage_frames;
      worst_in_outage_m = std::max(worst_in_outage_m, e.position_m);
    } else if (t_s >= 11.2 && t_s < 13.0) {
      worst_after_m = std::max(worst_after_m, e.position_m);
    }
  }
  std::printf("  %d frames without vision: worst position error %.1f mm; 0.2–2 s after: %.1f mm\n", outage_frames,
              worst_in_outage_m * 1e3, worst_after_m * 1e3);
  EXPECT_GE(outage_frames, 29);
  EXPECT_LT(worst_in_outage_m, 0.05);
  EXPECT_LT(worst_after_m, 0.006);
}

TEST(TwoStateEstimator, RefusesADenseSolutionThatContradictsTheImu) {
  // The white wall's failure: vision gone from 6 s to 10 s (dead reckoning, position σ grows to decimetres),
  // then from 10 s to 10.2 s the "dense terms" converge 2 m off (the wrong basin white_wall showed: 1.8–2.1 m): each of
  // those frames must fail the gate and the IMU carries them; from 10.2 s vision is right again and its correction of
  // the drift is accepted. At 3 s, while tracking, the dense terms are 5 cm off for 0.1 s: as inconsistent
  // by χ², but below the gate's minimum step (an over-confident estimator must still accept corrections
  // of that size), so used. Consistent frames stay far below the gate.
  const SimulatedRig rig("white_wall", 61);
  SimulatedVision vision(0.002, 0.1 * std::numbers::pi / 180.0, 62);
  const EstimatorOptions options;
  TwoStateEstimator estimator(options, imu::ImuOptions{}, rig.T_S_C);
  estimator.initialise(rig.frame_times_ns.front(), rig.initialState());
  const SE3d T_wrong_true(Eigen::Quaterniond::Identity(), Eigen::Vector3d(2.0, 0.0, 0.0));
  const SE3d T_slightly_off_true(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.0, 0.05, 0.0));
  int refused = 0;
  double worst_consistent_chi2 = 0.0, worst_small_pull_chi2 = 0.0, drift_m = 0.0, error_after_m = 0.0;
  for (std::size_t k = 1; k < rig.frame_times_ns.size(); ++k) {
    const std::int64_t t_ns = rig.frame_times_ns[k];
    const double t_s = nsToSeconds(t_ns - rig.frame_times_ns.front());
    if (t_s > 11.2) break;
    const bool outage = t_s >= 6.0 && t_s < 10.0;
    const bool wrong = t_s >= 10.0 && t_s < 10.2;
    const bool slightly_off = t_s >= 3.0 && t_s < 3.1;
    const NavState truth = rig.trueState(t_ns);
    const SE3d T_W_C_true(truth.q_W_C, truth.r_W_C);
    vision.observe(wrong ? T_wrong_true * T_W_C_true : slightly_off ? T_slightly_off_true * T_W_C_true : T_W_C_true);
    vision.setHealthy(!outage);
    FrameSolve solve;
    ASSERT_FALSE(
        estimator.track(t_ns, imu::bracketingSamples(rig.imu.samples, estimator.t_ns(), t_ns), &vision, solve));
    EXPECT_EQ(solve.vision_rejected, wrong) << "t = " << t_s << " s, vision χ² " << solve.vision_chi2;
    EXPECT_EQ(solve.vision_used, !wrong && !outage) << "t = " << t_s << " s";
    const double error_m = (estimator.state().r_W_C - truth.r_W_C).norm();
    if (wrong) {
      ++refused;
      EXPECT_GT(solve.vision_chi2, options.vision_gate_chi2);
      drift_m = std::max(drift_m, error_m);
    } else if (slightly_off) {
      worst_small_pull_chi2 = std::max(worst_small_pull_chi2, solve.vision_chi2);
    } else if (t_s >= 1.0 && !outage && !(t_s >= 3.1 && t_s < 3.6)) {  // not while pulling back from the 5 cm
      worst_consistent_chi2 = std::max(worst_consistent_chi2, solve.vision_chi2);
    }
    error_after_m = error_m;
  }
  std::printf(
      "  %d frames refused (dead-reckoning drift %.0f mm, %.1f mm 1 s after vision is right again);"
      " vision χ² of consistent frames at most %.1f, of the 5 cm pull %.0f (gate %.0f)\n",
      refused, drift_m * 1e3, error_after_m * 1e3, worst_consistent_chi2, worst_small_pull_chi2,
      options.vision_gate_chi2);
  EXPECT_GE(refused, 6);
  EXPECT_LT(drift_m, 0.5);         // the refused frames did not drag the state towards the wrong basin
  EXPECT_LT(error_after_m, 0.01);  // the drift correction itself was accepted
  EXPECT_LT(worst_consistent_chi2, 0.5 * options.vision_gate_chi2);
  EXPECT_GT(worst_small_pull_chi2, options.vision_gate_chi2);  // χ² alone would have refused it
}

struct OvershootRun {
  double worst_m = 0.0;  ///< worst position error from 3 s on
  int backtracks = 0;    ///< levels ended by a step that lost inliers
  int refused = 0;       ///< frames whose dense solution the gate refused (the IMU carried them)
};

/// Tracks the fast preset for 4 s with dense terms whose steps overshoot 30× from 3 s to 3.3 s.
OvershootRun trackWithOvershootingTerms(const EstimatorOptions& options, std::uint64_t seed) {
  const SimulatedRig rig("fast", seed);
  SimulatedVision vision(0.002, 0.1 * std::numbers::pi / 180.0, seed + 1);
  TwoStateEstimator estimator(options, imu::ImuOptions{}, rig.T_S_C);
  estimator.initialise(rig.frame_times_ns.front(), rig.initialState());
  OvershootRun run;
  for (std::size_t k = 1; k < rig.frame_times_ns.size(); ++k) {
    const std::int64_t t_ns = rig.frame_times_ns[k];
    const double t_s = nsToSeconds(t_ns - rig.frame_times_ns.front());
    if (t_s > 4.0) break;
    const NavState truth = rig.trueState(t_ns);
    vision.observe(SE3d(truth.q_W_C, truth.r_W_C));
    vision.setOvershoot(t_s >= 3.0 && t_s < 3.3 ? 30.0 : 1.0);
    FrameSolve solve;
    EXPECT_FALSE(
        estimator.track(t_ns, imu::bracketingSamples(rig.imu.samples, estimator.t_ns(), t_ns), &vision, solve));
    run.backtracks += solve.backtracks;
    run.refused += solve.vision_rejected ? 1 : 0;
    if (t_s >= 3.0) run.worst_m = std::max(run.worst_m, (estimator.state().r_W_C - truth.r_W_C).norm());
  }
  return run;
}

TEST(TwoStateEstimator, TakesBackAStepThatLosesTheDenseTermsInliers) {
  // Steps 30× too long leave the terms' basin and their inliers fall: each such step is taken back, the
  // dense solution stays usable (never refused) and the state stays on the path. With the check off the
  // iterates diverge (×29 per step), and what ends them depends on the last bits of the arithmetic: the
  // gate refuses the frame (the IMU carries it: vision lost) or a wrong solution below the gate's minimum
  // step is kept (position off by more than twice the checked run's worst). Several seeds, so that the
  // comparison does not rest on one draw; either outcome counts against the unchecked run.
  EstimatorOptions unchecked;
  unchecked.max_inlier_loss = 1.0;
  for (const std::uint64_t seed : {91u, 11u, 21u}) {
    const OvershootRun checked_run = trackWithOvershootingTerms(EstimatorOptions{}, seed);
    const OvershootRun unchecked_run = trackWithOvershootingTerms(unchecked, seed);
    std::printf(
        "  seed %2d, overshooting terms: worst position error %.1f mm with %d steps taken back and %d frames"
        " refused; unchecked %.1f mm, %d frames refused\n",
        static_cast<int>(seed), checked_run.worst_m * 1e3, checked_run.backtracks, checked_run.refused,
        unchecked_run.worst_m * 1e3, unchecked_run.refused);
    EXPECT_GT(checked_run.backtracks, 0) << "seed " << seed;
    EXPECT_EQ(checked_run.refused, 0) << "seed " << seed;
    EXPECT_LT(checked_run.worst_m, 0.015) << "seed " << seed;
    EXPECT_EQ(unchecked_run.backtracks, 0) << "seed " << seed;
    EXPECT_TRUE(unchecked_run.refused > 0 || unchecked_run.worst_m > 2.0 * checked_run.worst_m) << "seed " << seed;
  }
}

TEST(TwoStateEstimator, DeadReckoningUncertaintyGrowsAsTheAccelerometerNoiseDictates) {
  // Without vision the position is the twice-integrated accelerometer: its white noise alone spreads it
  // by σ_a·t^1.5/√3 per axis (0.052 m after 5 s with Table I's 8e-3 m/s²/√Hz; biases, velocity and
  // gravity errors add to that). The estimator's own covariance must say so — neither over-confident
  // (below that bound) nor uselessly loose — and the true error must fall within it. This is why a
  // blank wall that hides in-plane motion for 20 s cannot be tracked to centimetres by any estimator
  // fed this IMU (0.41 m of spread from white noise alone).
  const SimulatedRig rig("fast", 81);
  SimulatedVision vision(0.002, 0.1 * std::numbers::pi / 180.0, 82);
  TwoStateEstimator estimator(EstimatorOptions{}, imu::ImuOptions{}, rig.T_S_C);
  estimator.initialise(rig.frame_times_ns.front(), rig.initialState());
  constexpr double kOutageStart_s = 10.0, kOutage_s = 5.0;
  double sigma_end_m = 0.0, error_end_m = 0.0;
  for (std::size_t k = 1; k < rig.frame_times_ns.size(); ++k) {
    const std::int64_t t_ns = rig.frame_times_ns[k];
    const double t_s = nsToSeconds(t_ns - rig.frame_times_ns.front());
    if (t_s > kOutageStart_s + kOutage_s) break;
    const NavState truth = rig.trueState(t_ns);
    vision.observe(SE3d(truth.q_W_C, truth.r_W_C));
    vision.setHealthy(t_s < kOutageStart_s);
    FrameSolve solve;
    ASSERT_FALSE(
        estimator.track(t_ns, imu::bracketingSamples(rig.imu.samples, estimator.t_ns(), t_ns), &vision, solve));
    sigma_end_m = std::sqrt(estimator.covarianceDiagonal().segment<3>(kIdxR).maxCoeff());
    error_end_m = (estimator.state().r_W_C - truth.r_W_C).norm();
  }
  const double white_noise_bound_m = 8.0e-3 * std::pow(kOutage_s, 1.5) / std::sqrt(3.0);
  std::printf("  after %.0f s without vision: position σ %.3f m (white noise alone %.3f m), error %.3f m\n", kOutage_s,
              sigma_end_m, white_noise_bound_m, error_end_m);
  EXPECT_GT(sigma_end_m, 0.9 * white_noise_bound_m);
  EXPECT_LT(sigma_end_m, 6.0 * white_noise_bound_m);  // measured 3.9×: velocity, bias and gravity add the rest
  EXPECT_LT(error_end_m, 3.0 * std::sqrt(3.0) * sigma_end_m);
}

TEST(TwoStateEstimator, GyroModeEstimatesTheGyroBiasAndHoldsTheAccelerometerStates) {
  const SimulatedRig rig("quick_rotation", 31);
  SimulatedVision vision(0.002, 0.1 * std::numbers::pi / 180.0, 32);
  EstimatorOptions options;
  options.mode = InertialMode::kGyro;
  TwoStateEstimator estimator(options, imu::ImuOptions{}, rig.T_S_C);
  const NavState initial = rig.initialState();
  estimator.initialise(rig.frame_times_ns.front(), initial);
  double worst_gyro_after_15s = 0.0;
  for (std::size_t k = 1; k < rig.frame_times_ns.size(); ++k) {
    const std::int64_t t_ns = rig.frame_times_ns[k];
    const NavState truth = rig.trueState(t_ns);
    vision.observe(SE3d(truth.q_W_C, truth.r_W_C));
    FrameSolve solve;
    ASSERT_FALSE(
        estimator.track(t_ns, imu::bracketingSamples(rig.imu.samples, estimator.t_ns(), t_ns), &vision, solve));
    if (nsToSeconds(t_ns - rig.frame_times_ns.front()) >= 15.0) {
      worst_gyro_after_15s = std::max(worst_gyro_after_15s, (estimator.state().b_g - truth.b_g).norm());
    }
  }
  std::printf("  gyro mode: b_g max error after 15 s %.2e rad/s\n", worst_gyro_after_15s);
  EXPECT_LT(worst_gyro_after_15s, 2e-3);
  EXPECT_EQ(estimator.state().v_I_S, initial.v_I_S);
  EXPECT_EQ(estimator.state().b_a, initial.b_a);
  EXPECT_TRUE(estimator.state().q_I_W.isApprox(initial.q_I_W, 1e-12));
  const Vector18d variance = estimator.covarianceDiagonal();
  EXPECT_GT(variance.segment<3>(kIdxBg).minCoeff(), 0.0);
  EXPECT_EQ(variance.segment<3>(kIdxV).norm() + variance.segment<3>(kIdxBa).norm() + variance.segment<3>(kIdxG).norm(),
            0.0);
}

TEST(TwoStateEstimator, NeverEstimatesTheGravityGauge) {
  // q_I_W's rotation about gravity is unobservable: its row stays out of the prior and its variance is
  // reported as 0, while the two observable directions have a positive variance.
  const SimulatedRig rig("white_wall", 41);
  SimulatedVision vision(0.002, 0.002, 42);
  TwoStateEstimator estimator(EstimatorOptions{}, imu::ImuOptions{}, rig.T_S_C);
  estimator.initialise(rig.frame_times_ns.front(), rig.initialState());
  for (std::size_t k = 1; k < 60; ++k) {
    const std::int64_t t_ns = rig.frame_times_ns[k];
    const NavState truth = rig.trueState(t_ns);
    vision.observe(SE3d(truth.q_W_C, truth.r_W_C));
    FrameSolve solve;
    ASSERT_FALSE(
        estimator.track(t_ns, imu::bracketingSamples(rig.imu.samples, estimator.t_ns(), t_ns), &vision, solve));
  }
  EXPECT_EQ(estimator.priorInformation().row(kIdxG + 2).norm(), 0.0);
  const Vector18d variance = estimator.covarianceDiagonal();
  EXPECT_EQ(variance[kIdxG + 2], 0.0);
  EXPECT_GT(variance[kIdxG], 0.0);
  EXPECT_GT(variance[kIdxG + 1], 0.0);
  EXPECT_GT(variance.head<15>().minCoeff(), 0.0);
}

TEST(TwoStateEstimator, ReportsBrokenImuDataAndKeepsItsState) {
  const SimulatedRig rig("white_wall", 51, false);
  SimulatedVision vision(0.002, 0.002, 52);
  TwoStateEstimator estimator(EstimatorOptions{}, imu::ImuOptions{}, rig.T_S_C);
  estimator.initialise(rig.frame_times_ns.front(), rig.initialState());
  const std::int64_t t1_ns = rig.frame_times_ns[1];
  std::vector<ImuSample> samples(imu::bracketingSamples(rig.imu.samples, estimator.t_ns(), t1_ns).begin(),
                                 imu::bracketingSamples(rig.imu.samples, estimator.t_ns(), t1_ns).end());
  ASSERT_GE(samples.size(), 5u);
  samples.erase(samples.begin() + 2, samples.begin() + 4);  // two dropped samples: a 15 ms gap
  vision.observe(SE3d(rig.trueState(t1_ns).q_W_C, rig.trueState(t1_ns).r_W_C));
  FrameSolve solve;
  const NavState before = estimator.state();
  const auto issue = estimator.track(t1_ns, samples, &vision, solve);
  ASSERT_TRUE(issue.has_value());
  EXPECT_EQ(issue->problem, imu::ImuSampleProblem::kGap);
  EXPECT_EQ(estimator.t_ns(), rig.frame_times_ns.front());
  EXPECT_EQ(estimator.state().r_W_C, before.r_W_C);
  EXPECT_EQ(vision.evaluations(), 0);
}

/// A state moved as a loop closure's rigid correction moves it (TwoStateEstimator::moveWithMap's rule).
NavState movedWithMap(NavState x, const SE3d& T_Wnew_Wold) {
  const Eigen::Matrix3d R_I =
      x.q_I_W.toRotationMatrix() * T_Wnew_Wold.rotationMatrix() * x.q_I_W.toRotationMatrix().transpose();
  x.r_W_C = T_Wnew_Wold * x.r_W_C;
  x.q_W_C = T_Wnew_Wold.quaternion() * x.q_W_C;
  x.v_I_S = R_I * x.v_I_S;
  return x;
}

/// The prior's energy of state y: δᵀH*δ + 2b*ᵀδ, δ = y ⊟ state().
double priorEnergy(const TwoStateEstimator& estimator, const NavState& y) {
  const Vector18d delta = boxMinus(y, estimator.state());
  return delta.dot(estimator.priorInformation() * delta) + 2.0 * estimator.priorGradient().dot(delta);
}

// A loop closure turns the map about gravity and shifts it: the state moves with it, keeps its velocity
// relative to the IMU's body, and the marginalisation prior says exactly what it said before about every
// state moved the same way.
TEST(TwoStateEstimator, MovesWithTheMapAndCarriesItsPrior) {
  const SimulatedRig rig("fast", 21);
  SimulatedVision vision(0.002, 0.1 * std::numbers::pi / 180.0, 22);
  TwoStateEstimator estimator(EstimatorOptions{}, imu::ImuOptions{}, rig.T_S_C);
  estimator.initialise(rig.frame_times_ns.front(), rig.initialState());
  for (std::size_t k = 1; k < 60; ++k) {  // two seconds: a prior with correlations and a moving body
    const std::int64_t t_ns = rig.frame_times_ns[k];
    const NavState truth = rig.trueState(t_ns);
    vision.observe(SE3d(truth.q_W_C, truth.r_W_C));
    FrameSolve solve;
    ASSERT_FALSE(
        estimator.track(t_ns, imu::bracketingSamples(rig.imu.samples, estimator.t_ns(), t_ns), &vision, solve));
  }
  const NavState before = estimator.state();
  ASSERT_GT(before.v_I_S.norm(), 0.1);
  std::vector<NavState> probes;
  std::mt19937 random(5);
  std::normal_distribution<double> normal(0.0, 0.05);
  for (int i = 0; i < 5; ++i) {
    Vector18d delta;
    for (int d = 0; d < kStateDim; ++d) delta[d] = normal(random);
    // Same gravity as the state: a state with another q_I_W turns its velocity by its own R_I, which the
    // prior's transport (one J at the state's q_I_W) matches to first order only.
    delta.segment<3>(kIdxG).setZero();
    probes.push_back(boxPlus(before, delta));
  }
  std::vector<double> energies;
  for (const NavState& y : probes) energies.push_back(priorEnergy(estimator, y));

  const Eigen::Vector3d up_W = -gravityInW(before);
  const SE3d T_Wnew_Wold(Eigen::Quaterniond(Eigen::AngleAxisd(0.05, up_W)), Eigen::Vector3d(0.04, -0.02, 0.03));
  estimator.moveWithMap(T_Wnew_Wold);
  const NavState after = estimator.state();
  EXPECT_LT((after.r_W_C - T_Wnew_Wold * before.r_W_C).norm(), 1e-12);
  EXPECT_LT(logSO3(after.q_W_C * (T_Wnew_Wold.quaternion() * before.q_W_C).conjugate()).norm(), 1e-12);
  EXPECT_LT(logSO3(after.q_I_W * before.q_I_W.conjugate()).norm(), 1e-15) << "gravity stays";
  // The IMU's velocity in its own body frame: v_S = R_S_I·v_I, R_I_S = R_I_W·R_W_C·R_C_S.
  const auto bodyVelocity = [&](const NavState& x) {
    const Eigen::Matrix3d R_I_S =
        x.q_I_W.toRotationMatrix() * x.q_W_C.toRotationMatrix() * rig.T_S_C.rotationMatrix().transpose();
    return Eigen::Vector3d(R_I_S.transpose() * x.v_I_S);
  };
  EXPECT_LT((bodyVelocity(after) - bodyVelocity(before)).norm(), 1e-12);
  for (std::size_t i = 0; i < probes.size(); ++i) {
    EXPECT_NEAR(priorEnergy(estimator, movedWithMap(probes[i], T_Wnew_Wold)), energies[i], 1e-9 * energies[i])
        << "probe " << i;
  }
}

}  // namespace
}  // namespace vifusion::estimator
