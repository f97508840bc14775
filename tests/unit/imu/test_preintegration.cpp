#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "imu_test_utils.hpp"
#include "vifusion/core/numeric_diff.hpp"
#include "vifusion/core/so3.hpp"
#include "vifusion/imu/preintegration.hpp"
#include "vifusion/sim/normal_rng.hpp"
#include "vifusion/test/eigen_asserts.hpp"

namespace vifusion::imu {
namespace {

using test::integrateOrFail;
using test::kPeriodNs;
using test::rotationDifference;
using test::smoothSamples;
using Vector6d = Eigen::Matrix<double, 6, 1>;
using Vector9d = Eigen::Matrix<double, 9, 1>;
using Vector15d = Eigen::Matrix<double, kDeltaDim, 1>;

constexpr std::int64_t kStartNs = 2'000'000'000;

/// [Δp, Δφ, Δv] of `pre` relative to `reference` (Δφ = log(ΔR_refᵀ·ΔR), the right perturbation).
Vector9d deltaDifference(const ImuDeltas& pre, const ImuDeltas& reference) {
  Vector9d d;
  d << pre.dp_S0_m - reference.dp_S0_m, rotationDifference(reference.q_S0_S1, pre.q_S0_S1),
      pre.dv_S0_mps - reference.dv_S0_mps;
  return d;
}

TEST(Preintegration, InterpolatesLinearReadingsExactlyToTheFrameTimes) {
  // Readings linear in time between samples are what interpolation assumes; then a rotation about a fixed
  // axis has the exact angle ∫ω dt, and with no rotation Δv = ∫a dt exactly. Frame times fall between
  // samples: integrating from the sample before t0 instead would be 4.2 ms too long at the start.
  const std::int64_t t0_ns = kStartNs + 12'345'678;  // 2.4 samples in
  const std::int64_t t1_ns = kStartNs + 45'678'901;  // 1/30 s later
  const double t0_s = nsToSeconds(t0_ns - kStartNs);
  const double t1_s = nsToSeconds(t1_ns - kStartNs);
  const Eigen::Vector3d axis = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
  const double w0 = 1.5, w1 = -20.0;                                  // ω(s) = w0 + w1·s [rad/s]
  const Eigen::Vector3d a0(0.4, -1.2, 9.81), jerk(30.0, 5.0, -12.0);  // a(s) = a0 + jerk·s [m/s²]

  std::vector<ImuSample> rotating(12), accelerating(12);
  for (std::size_t k = 0; k < rotating.size(); ++k) {
    const double s = static_cast<double>(k) * nsToSeconds(kPeriodNs);
    rotating[k] = {kStartNs + static_cast<std::int64_t>(k) * kPeriodNs, (w0 + w1 * s) * axis, Eigen::Vector3d::Zero()};
    accelerating[k] = {rotating[k].t_ns, Eigen::Vector3d::Zero(), a0 + jerk * s};
  }
  const ImuPreintegrator integrator{ImuOptions{}};
  const PreintegratedImu turn =
      integrateOrFail(integrator, rotating, t0_ns, t1_ns, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  const PreintegratedImu push =
      integrateOrFail(integrator, accelerating, t0_ns, t1_ns, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());

  EXPECT_EQ(turn.t0_ns, t0_ns);
  EXPECT_EQ(turn.t1_ns, t1_ns);
  EXPECT_EQ(turn.dt_s, nsToSeconds(t1_ns - t0_ns));
  const double angle_rad = w0 * (t1_s - t0_s) + 0.5 * w1 * (t1_s * t1_s - t0_s * t0_s);
  EXPECT_ROTATION_NEAR(turn.delta.q_S0_S1, expSO3(angle_rad * axis), 1e-14);
  EXPECT_MATRIX_NEAR(turn.delta.dv_S0_mps, Eigen::Vector3d::Zero(), 0.0);

  const double T = t1_s - t0_s;
  const Eigen::Vector3d a_t0 = a0 + jerk * t0_s;
  EXPECT_ROTATION_NEAR(push.delta.q_S0_S1, Eigen::Quaterniond::Identity(), 0.0);
  EXPECT_MATRIX_NEAR(push.delta.dv_S0_mps, a_t0 * T + 0.5 * jerk * T * T, 1e-14);
  // Δp: the mid-point rule holds â at its mean over a step of h, which adds exactly jerk·h³/12 per step
  // (Δv being exact); the steps are cut at t0, every sample inside, and t1.
  double sum_h3 = 0.0;
  std::int64_t begin_ns = t0_ns;
  for (const ImuSample& s : accelerating) {
    if (s.t_ns <= t0_ns) continue;
    const double h_s = nsToSeconds(std::min(s.t_ns, t1_ns) - begin_ns);
    sum_h3 += h_s * h_s * h_s;
    begin_ns = s.t_ns;
    if (s.t_ns >= t1_ns) break;
  }
  const Eigen::Vector3d dp_exact = 0.5 * a_t0 * T * T + jerk * T * T * T / 6.0;
  EXPECT_MATRIX_NEAR(push.delta.dp_S0_m, dp_exact + jerk * sum_h3 / 12.0, 1e-15);
  std::printf("  Δp of the mid-point rule on a linear ramp: %.2e m from the exact integral, as predicted\n",
              (push.delta.dp_S0_m - dp_exact).norm());
}

TEST(Preintegration, SplitsAtASampleComposeToTheWhole) {
  // [t0, tm] then [tm, t1] with tm on a sample covers the same steps as [t0, t1]; the deltas compose as
  // ΔR = ΔR_a·ΔR_b, Δv = Δv_a + ΔR_a·Δv_b, Δp = Δp_a + Δv_a·Δt_b + ΔR_a·Δp_b.
  const std::vector<ImuSample> samples = smoothSamples(11, kStartNs, 40);
  const std::int64_t t0_ns = kStartNs + 3'210'000, tm_ns = kStartNs + 60'000'000, t1_ns = kStartNs + 151'234'567;
  const Eigen::Vector3d b_g(0.01, -0.02, 0.005), b_a(0.1, 0.05, -0.2);
  const ImuPreintegrator integrator{ImuOptions{}};
  const PreintegratedImu a = integrateOrFail(integrator, samples, t0_ns, tm_ns, b_g, b_a);
  const PreintegratedImu b = integrateOrFail(integrator, samples, tm_ns, t1_ns, b_g, b_a);
  const PreintegratedImu whole = integrateOrFail(integrator, samples, t0_ns, t1_ns, b_g, b_a);
  const Eigen::Quaterniond& q_a = a.delta.q_S0_S1;
  EXPECT_ROTATION_NEAR(whole.delta.q_S0_S1, q_a * b.delta.q_S0_S1, 1e-14);
  EXPECT_MATRIX_NEAR(whole.delta.dv_S0_mps, a.delta.dv_S0_mps + q_a * b.delta.dv_S0_mps, 1e-14);
  EXPECT_MATRIX_NEAR(whole.delta.dp_S0_m, a.delta.dp_S0_m + a.delta.dv_S0_mps * b.dt_s + q_a * b.delta.dp_S0_m, 1e-14);
}

/// The nine deltas as a function of the six linearisation biases [b_g; b_a], relative to `reference`.
Vector9d deltasAtBias(const ImuPreintegrator& integrator, const std::vector<ImuSample>& samples, std::int64_t t0_ns,
                      std::int64_t t1_ns, const Vector6d& b, const ImuDeltas& reference) {
  const PreintegratedImu pre = integrateOrFail(integrator, samples, t0_ns, t1_ns, b.head<3>(), b.tail<3>());
  return deltaDifference(pre.delta, reference);
}

TEST(Preintegration, BiasJacobiansMatchNumericDifferentiation) {
  const ImuPreintegrator integrator{ImuOptions{}};
  double worst_frame = 0.0, worst_long = 0.0;
  for (unsigned seed = 1; seed <= 6; ++seed) {
    test::RandomInputs rnd(seed);
    const std::vector<ImuSample> samples = smoothSamples(seed, kStartNs, 120);
    // One 30 Hz frame and a 0.5 s stretch (where the cross terms have grown), off the sample grid.
    const std::int64_t t0_ns = kStartNs + 7'654'321;
    for (const std::int64_t dt_ns : {std::int64_t{33'333'333}, std::int64_t{500'000'000}}) {
      const std::int64_t t1_ns = t0_ns + dt_ns;
      Vector6d b_lin;
      b_lin << rnd.vector<3>(0.03), rnd.vector<3>(0.3);
      const PreintegratedImu pre = integrateOrFail(integrator, samples, t0_ns, t1_ns, b_lin.head<3>(), b_lin.tail<3>());

      Eigen::Matrix<double, 9, 6> J = Eigen::Matrix<double, 9, 6>::Zero();  // rows [Δp, Δφ, Δv]
      J.block<3, 3>(0, 0) = pre.d_p_d_bg;
      J.block<3, 3>(0, 3) = pre.d_p_d_ba;
      J.block<3, 3>(3, 0) = pre.d_R_d_bg;
      J.block<3, 3>(6, 0) = pre.d_v_d_bg;
      J.block<3, 3>(6, 3) = pre.d_v_d_ba;
      const auto f = [&](const Vector6d& b) { return deltasAtBias(integrator, samples, t0_ns, t1_ns, b, pre.delta); };
      const Eigen::Matrix<double, 9, 6> J_num = numericJacobian(f, b_lin);
      // Entries reach ~0.05 over a frame and ~1 over 0.5 s; central differences are good to ~1e-9 of that.
      EXPECT_MATRIX_NEAR(J, J_num, 1e-8) << "seed " << seed << ", Δt " << dt_ns << " ns";
      double& worst = dt_ns < 100'000'000 ? worst_frame : worst_long;
      worst = std::max(worst, (J - J_num).cwiseAbs().maxCoeff());
    }
  }
  std::printf("  largest |analytic − numeric| over the bias Jacobians: %.2e (1/30 s), %.2e (0.5 s)\n", worst_frame,
              worst_long);
}

TEST(Preintegration, FirstOrderBiasCorrectionAgreesWithReintegrationToSecondOrder) {
  // δb = s·d: the correction's error against re-integrating at b_lin + δb must shrink as s², and stay far
  // below the noise at the re-integration threshold.
  const ImuPreintegrator integrator{ImuOptions{}};
  const std::vector<ImuSample> samples = smoothSamples(21, kStartNs, 20);
  const std::int64_t t0_ns = kStartNs + 4'000'000, t1_ns = t0_ns + 33'333'333;
  const Eigen::Vector3d b_g_lin(0.01, -0.015, 0.02), b_a_lin(-0.1, 0.2, 0.05);
  const PreintegratedImu pre = integrateOrFail(integrator, samples, t0_ns, t1_ns, b_g_lin, b_a_lin);
  const Eigen::Vector3d d_bg = Eigen::Vector3d(0.6, -0.3, 0.75).normalized() * 0.03;  // the 1σ prior [rad/s]
  const Eigen::Vector3d d_ba = Eigen::Vector3d(-0.2, 0.9, 0.4).normalized() * 0.1;    // the 1σ prior [m/s²]

  const auto error = [&](double s) {
    const ImuDeltas first_order = pre.corrected(b_g_lin + s * d_bg, b_a_lin + s * d_ba);
    const PreintegratedImu redone =
        integrateOrFail(integrator, samples, t0_ns, t1_ns, b_g_lin + s * d_bg, b_a_lin + s * d_ba);
    return deltaDifference(first_order, redone.delta);
  };
  Vector9d previous = error(1.0);
  std::printf("  first-order vs re-integrated, ‖δb_g‖·Δt = 1e-3 rad: |Δp| %.2e m, |Δφ| %.2e rad, |Δv| %.2e m/s\n",
              previous.head<3>().norm(), previous.segment<3>(3).norm(), previous.tail<3>().norm());
  for (const double s : {0.5, 0.25, 0.125}) {
    const Vector9d current = error(s);
    for (int block = 0; block < 3; ++block) {
      const double ratio = previous.segment<3>(3 * block).norm() / current.segment<3>(3 * block).norm();
      EXPECT_NEAR(ratio, 4.0, 0.3) << "block " << block << " at s = " << s;
    }
    previous = current;
  }
  // At the threshold ‖δb_g‖·Δt = 1e-4 rad (s = 0.1): what preintegration.hpp quotes, against white noise
  // of σ_g·√Δt ≈ 2e-4 rad and σ_a·√Δt ≈ 1.5e-3 m/s over the frame.
  const Vector9d at_threshold = error(0.1);
  std::printf("  at the threshold 1e-4 rad: |Δp| %.2e m, |Δφ| %.2e rad, |Δv| %.2e m/s\n", at_threshold.head<3>().norm(),
              at_threshold.segment<3>(3).norm(), at_threshold.tail<3>().norm());
  EXPECT_LT(at_threshold.head<3>().norm(), 1e-9);
  EXPECT_LT(at_threshold.segment<3>(3).norm(), 1e-9);
  EXPECT_LT(at_threshold.tail<3>().norm(), 1e-7);
}

TEST(Preintegration, ReintegrationRuleFollowsTheGyroBiasChange) {
  const ImuPreintegrator integrator{ImuOptions{}};
  const std::vector<ImuSample> samples = smoothSamples(5, kStartNs, 20);
  const std::int64_t t0_ns = kStartNs + 1'000'000, t1_ns = t0_ns + 40'000'000;  // Δt = 0.04 s
  const Eigen::Vector3d b_g_lin(0.002, 0.0, -0.001), b_a_lin(0.1, 0.1, 0.1);
  const PreintegratedImu pre = integrateOrFail(integrator, samples, t0_ns, t1_ns, b_g_lin, b_a_lin);
  EXPECT_EQ(pre.reintegrate_above_rad, 1e-4);
  const Eigen::Vector3d direction = Eigen::Vector3d(1.0, 2.0, -2.0) / 3.0;
  // 1e-4 rad / 0.04 s = 2.5e-3 rad/s of gyro-bias change is the limit; accelerometer biases never matter.
  EXPECT_FALSE(pre.needsReintegration(b_g_lin + 2.4e-3 * direction));
  EXPECT_TRUE(pre.needsReintegration(b_g_lin + 2.6e-3 * direction));
  const Eigen::Vector3d b_g_new = b_g_lin + 2.6e-3 * direction;
  const PreintegratedImu redone = integrateOrFail(integrator, samples, t0_ns, t1_ns, b_g_new, b_a_lin + direction);
  EXPECT_FALSE(redone.needsReintegration(b_g_new));
  // At its own linearisation point the correction is the identity (up to re-normalising ΔR).
  const ImuDeltas same = redone.corrected(b_g_new, b_a_lin + direction);
  EXPECT_MATRIX_NEAR(deltaDifference(same, redone.delta), Vector9d::Zero(), 1e-15);
}

TEST(Preintegration, SaturatedSamplesAreDownWeighted) {
  // One clipped sample inflates the white noise of the two steps that use it by 100² in variance. Readings
  // along S's x axis only keep the x entries of δφ (pure x rotation) and δv (force along x) free of every
  // other term, so their variances are exactly σ²·h·Σ(factor²) over the N steps.
  const ImuOptions options;
  const ImuPreintegrator integrator{options};
  constexpr int kSteps = 10;
  const double h = nsToSeconds(kPeriodNs);
  const auto stream = [&](const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel, int special,
                          const Eigen::Vector3d& special_gyro, const Eigen::Vector3d& special_accel) {
    std::vector<ImuSample> samples(kSteps + 1);
    for (int k = 0; k <= kSteps; ++k) {
      const bool is_special = k == special;
      samples[k] = {kStartNs + k * kPeriodNs, is_special ? special_gyro : gyro, is_special ? special_accel : accel};
    }
    return integrateOrFail(integrator, samples, kStartNs, kStartNs + kSteps * kPeriodNs, Eigen::Vector3d::Zero(),
                           Eigen::Vector3d::Zero());
  };
  const double var_g = options.noise.gyro_noise_density * options.noise.gyro_noise_density;
  const double var_a = options.noise.accel_noise_density * options.noise.accel_noise_density;
  const double inflated_steps = kSteps - 2 + 2 * 100.0 * 100.0;
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();

  const PreintegratedImu gyro_clipped = stream(7.0 * x, Eigen::Vector3d::Zero(), 4, 7.8 * x, Eigen::Vector3d::Zero());
  const PreintegratedImu gyro_below = stream(7.0 * x, Eigen::Vector3d::Zero(), 4, 7.79 * x, Eigen::Vector3d::Zero());
  EXPECT_EQ(gyro_clipped.gyro_saturated_steps, 2);
  EXPECT_EQ(gyro_clipped.accel_saturated_steps, 0);
  EXPECT_EQ(gyro_below.gyro_saturated_steps, 0);
  EXPECT_NEAR(gyro_clipped.covariance(kDeltaIdxPhi, kDeltaIdxPhi) / (var_g * h * inflated_steps), 1.0, 1e-6);
  EXPECT_NEAR(gyro_below.covariance(kDeltaIdxPhi, kDeltaIdxPhi) / (var_g * h * kSteps), 1.0, 1e-6);

  const PreintegratedImu accel_clipped =
      stream(Eigen::Vector3d::Zero(), 50.0 * x, 7, Eigen::Vector3d::Zero(), -176.0 * x);
  const PreintegratedImu accel_below =
      stream(Eigen::Vector3d::Zero(), 50.0 * x, 7, Eigen::Vector3d::Zero(), -175.9 * x);
  EXPECT_EQ(accel_clipped.accel_saturated_steps, 2);
  EXPECT_EQ(accel_clipped.gyro_saturated_steps, 0);
  EXPECT_EQ(accel_below.accel_saturated_steps, 0);
  EXPECT_NEAR(accel_clipped.covariance(kDeltaIdxV, kDeltaIdxV) / (var_a * h * inflated_steps), 1.0, 1e-6);
  EXPECT_NEAR(accel_below.covariance(kDeltaIdxV, kDeltaIdxV) / (var_a * h * kSteps), 1.0, 1e-6);
  std::printf("  δφ_x variance ×%.0f, δv_x variance ×%.0f with one clipped sample in %d steps\n",
              gyro_clipped.covariance(kDeltaIdxPhi, kDeltaIdxPhi) / gyro_below.covariance(kDeltaIdxPhi, kDeltaIdxPhi),
              accel_clipped.covariance(kDeltaIdxV, kDeltaIdxV) / accel_below.covariance(kDeltaIdxV, kDeltaIdxV),
              kSteps);
}

TEST(Preintegration, OneShortStepAlreadyHasAnInvertibleCovariance) {
  // A 1 ms interval inside one sample interval: a single step, where a held-sample position term would
  // leave (δv, δp) perfectly correlated.
  const ImuPreintegrator integrator{ImuOptions{}};
  const std::vector<ImuSample> samples = smoothSamples(8, kStartNs, 4);
  const PreintegratedImu pre = integrateOrFail(integrator, samples, kStartNs + 6'000'000, kStartNs + 7'000'000,
                                               Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  EXPECT_EQ(pre.covariance.llt().info(), Eigen::Success);
  const Matrix15d product = pre.information * pre.covariance;
  EXPECT_MATRIX_NEAR(product, Matrix15d::Identity(), 1e-6);
}

/// Monte-Carlo check of the propagated covariance: noisy copies of one sample stream (white noise of the
/// discrete σ·√rate per sample and a bias random walk per sample, as the simulator makes them) are
/// integrated, and the spread of η = [δp, δφ, δv, δb_g, δb_a] against the noise-free deltas is compared
/// with the model: variances within 15 %, correlation coefficients within 0.1.
void expectCovarianceMatchesMonteCarlo(const ImuOptions& options, std::int64_t dt_ns, const char* label) {
  constexpr int kRuns = 2000;
  const ImuPreintegrator integrator{options};
  const int count = static_cast<int>(dt_ns / kPeriodNs) + 1;
  const std::vector<ImuSample> truth = smoothSamples(31, kStartNs, count);
  const std::int64_t t0_ns = kStartNs, t1_ns = kStartNs + dt_ns;  // on samples: the walk starts at t0
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  const PreintegratedImu model = integrateOrFail(integrator, truth, t0_ns, t1_ns, zero, zero);

  const double h = nsToSeconds(kPeriodNs);
  const double sigma_g = options.noise.gyro_noise_density / std::sqrt(h);
  const double sigma_a = options.noise.accel_noise_density / std::sqrt(h);
  const double step_bg = options.noise.gyro_random_walk * std::sqrt(h);
  const double step_ba = options.noise.accel_random_walk * std::sqrt(h);
  sim::NormalRng normal(2024);
  const auto gaussian = [&] { return Eigen::Vector3d(normal(), normal(), normal()); };

  Vector15d sum = Vector15d::Zero();
  Matrix15d sum_sq = Matrix15d::Zero();
  std::vector<ImuSample> noisy = truth;
  for (int run = 0; run < kRuns; ++run) {
    Eigen::Vector3d b_g = zero, b_a = zero;
    for (std::size_t k = 0; k < truth.size(); ++k) {
      noisy[k].gyro_rad_s = truth[k].gyro_rad_s + b_g + sigma_g * gaussian();
      noisy[k].accel_mps2 = truth[k].accel_mps2 + b_a + sigma_a * gaussian();
      if (k + 1 < truth.size()) {
        b_g += step_bg * gaussian();
        b_a += step_ba * gaussian();
      }
    }
    const PreintegratedImu pre = integrateOrFail(integrator, noisy, t0_ns, t1_ns, zero, zero);
    Vector15d eta;
    eta << deltaDifference(pre.delta, model.delta), b_g, b_a;
    sum += eta;
    sum_sq += eta * eta.transpose();
  }
  const Vector15d mean = sum / kRuns;
  const Matrix15d sampled = (sum_sq - kRuns * mean * mean.transpose()) / (kRuns - 1);

  double worst_ratio = 1.0, worst_correlation = 0.0;
  for (int i = 0; i < kDeltaDim; ++i) {
    const double ratio = sampled(i, i) / model.covariance(i, i);
    EXPECT_NEAR(ratio, 1.0, 0.15) << label << ": variance " << i;
    if (std::abs(ratio - 1.0) > std::abs(worst_ratio - 1.0)) worst_ratio = ratio;
    for (int j = 0; j < i; ++j) {
      const double rho_sampled = sampled(i, j) / std::sqrt(sampled(i, i) * sampled(j, j));
      const double rho_model = model.covariance(i, j) / std::sqrt(model.covariance(i, i) * model.covariance(j, j));
      EXPECT_NEAR(rho_sampled, rho_model, 0.1) << label << ": correlation (" << i << ", " << j << ")";
      worst_correlation = std::max(worst_correlation, std::abs(rho_sampled - rho_model));
    }
  }
  std::printf("  %s: sampled/model variance worst %.3f, correlation worst |Δρ| %.3f (%d runs)\n", label, worst_ratio,
              worst_correlation, kRuns);
}

TEST(Preintegration, CovarianceMatchesMonteCarloWithTableOneNoise) {
  expectCovarianceMatchesMonteCarlo(ImuOptions{}, 500'000'000, "Table I, 0.5 s");
}

TEST(Preintegration, CovarianceMatchesMonteCarloWithStrongBiasWalks) {
  // Walks ~1000× Table I's, so that the walk's coupling into δφ, δv, δp is as large as the white noise's
  // over 0.5 s and the cross terms of F are checked, not just the diagonal.
  ImuOptions options;
  options.noise.gyro_random_walk = 4e-3;
  options.noise.accel_random_walk = 3e-2;
  expectCovarianceMatchesMonteCarlo(options, 500'000'000, "strong walks, 0.5 s");
}

}  // namespace
}  // namespace vifusion::imu
