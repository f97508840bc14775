#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "sim_test_utils.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/core/so3.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/sim/imu_simulator.hpp"
#include "vifusion/sim/presets.hpp"
#include "vifusion/sim/trajectory_fit.hpp"
#include "vifusion/test/eigen_asserts.hpp"

namespace vifusion::sim {
namespace {

const Eigen::Vector3d kG_W_mps2(0.0, -9.81, 0.0);

ImuSimOptions idealImu() {
  ImuSimOptions options;
  options.add_noise = false;
  options.add_biases = false;
  return options;
}

/// A spline that stays at p = 0 with constant orientation q (all control points equal).
Se3Spline staticSpline(const Eigen::Quaterniond& q_W_S, double duration_s) {
  const int segments = static_cast<int>(std::lround(duration_s));
  return Se3Spline(0, kNsPerSecond, std::vector<Eigen::Vector3d>(segments + 5, Eigen::Vector3d::Zero()),
                   std::vector<Eigen::Quaterniond>(segments + 5, q_W_S));
}

// ---------------------------------------------------------------------------------------------------------
// Strapdown integration of the simulated IMU, the acceptance check of the simulator: noise- and bias-free
// samples must reproduce the spline's own pose and velocity.
//
// State (q_W_S, v_W, p_W) with q̇ = ½·q⊗(0, ω), v̇ = R(q)·f + g, ṗ = v, advanced by classical RK4 from sample k
// to k + 1. RK4 needs ω and f at the interval's midpoint; they come from a cubic through the four nearest
// samples (k − 1 … k + 2, shifted inwards at the ends), whose O(Δt⁴) error matches RK4's order. Linear
// interpolation is also reported: it is only O(Δt²) and is the weak point of a 200 Hz integrator.
enum class Interpolation { kLinear, kCubic };

struct NavState {
  Eigen::Vector4d q_wxyz;  ///< q_W_S as (w, x, y, z); normalised after each step
  Eigen::Vector3d v_W_mps;
  Eigen::Vector3d p_W_m;
};

struct NavDerivative {
  Eigen::Vector4d q_dot;
  Eigen::Vector3d v_dot;
  Eigen::Vector3d p_dot;
};

Eigen::Quaterniond toQuaternion(const Eigen::Vector4d& wxyz) {
  return Eigen::Quaterniond(wxyz[0], wxyz[1], wxyz[2], wxyz[3]).normalized();
}

NavDerivative derivative(const NavState& s, const Eigen::Vector3d& omega_S, const Eigen::Vector3d& f_S) {
  const Eigen::Quaterniond q(s.q_wxyz[0], s.q_wxyz[1], s.q_wxyz[2], s.q_wxyz[3]);
  const Eigen::Quaterniond q_dot = q * Eigen::Quaterniond(0.0, 0.5 * omega_S.x(), 0.5 * omega_S.y(), 0.5 * omega_S.z());
  return {Eigen::Vector4d(q_dot.w(), q_dot.x(), q_dot.y(), q_dot.z()), toQuaternion(s.q_wxyz) * f_S + kG_W_mps2,
          s.v_W_mps};
}

NavState advance(const NavState& s, const NavDerivative& d, double h_s) {
  return {s.q_wxyz + h_s * d.q_dot, s.v_W_mps + h_s * d.v_dot, s.p_W_m + h_s * d.p_dot};
}

/// Measurement (gyro, accel) halfway between samples k and k + 1.
std::array<Eigen::Vector3d, 2> midpointMeasurement(const std::vector<ImuSample>& samples, std::size_t k,
                                                   Interpolation interpolation) {
  if (interpolation == Interpolation::kLinear) {
    return {0.5 * (samples[k].gyro_rad_s + samples[k + 1].gyro_rad_s),
            0.5 * (samples[k].accel_mps2 + samples[k + 1].accel_mps2)};
  }
  // Lagrange cubic through 4 equally spaced samples, evaluated at x (in sample units from the first).
  const std::size_t first = std::min(k == 0 ? 0 : k - 1, samples.size() - 4);
  const double x = static_cast<double>(k - first) + 0.5;
  std::array<double, 4> weight{};
  for (int i = 0; i < 4; ++i) {
    weight[i] = 1.0;
    for (int j = 0; j < 4; ++j) {
      if (j != i) weight[i] *= (x - j) / static_cast<double>(i - j);
    }
  }
  std::array<Eigen::Vector3d, 2> out{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  for (int i = 0; i < 4; ++i) {
    out[0] += weight[i] * samples[first + i].gyro_rad_s;
    out[1] += weight[i] * samples[first + i].accel_mps2;
  }
  return out;
}

struct IntegrationError {
  double max_position_mm = 0.0;
  double max_attitude_deg = 0.0;
  double max_velocity_mps = 0.0;
};

IntegrationError integrateAgainstTruth(const ImuSimResult& imu, Interpolation interpolation) {
  const GroundTruthState& first = imu.states.front();
  NavState s{Eigen::Vector4d(first.q_W_S.w(), first.q_W_S.x(), first.q_W_S.y(), first.q_W_S.z()), first.v_W_S,
             first.p_W_S};
  IntegrationError error;
  for (std::size_t k = 0; k + 1 < imu.samples.size(); ++k) {
    const double h_s = nsToSeconds(imu.samples[k + 1].t_ns - imu.samples[k].t_ns);
    const auto mid = midpointMeasurement(imu.samples, k, interpolation);
    const NavDerivative k1 = derivative(s, imu.samples[k].gyro_rad_s, imu.samples[k].accel_mps2);
    const NavDerivative k2 = derivative(advance(s, k1, 0.5 * h_s), mid[0], mid[1]);
    const NavDerivative k3 = derivative(advance(s, k2, 0.5 * h_s), mid[0], mid[1]);
    const NavDerivative k4 =
        derivative(advance(s, k3, h_s), imu.samples[k + 1].gyro_rad_s, imu.samples[k + 1].accel_mps2);
    s.q_wxyz += h_s / 6.0 * (k1.q_dot + 2.0 * k2.q_dot + 2.0 * k3.q_dot + k4.q_dot);
    s.v_W_mps += h_s / 6.0 * (k1.v_dot + 2.0 * k2.v_dot + 2.0 * k3.v_dot + k4.v_dot);
    s.p_W_m += h_s / 6.0 * (k1.p_dot + 2.0 * k2.p_dot + 2.0 * k3.p_dot + k4.p_dot);
    s.q_wxyz.normalize();

    const GroundTruthState& truth = imu.states[k + 1];
    error.max_position_mm = std::max(error.max_position_mm, 1e3 * (s.p_W_m - truth.p_W_S).norm());
    error.max_velocity_mps = std::max(error.max_velocity_mps, (s.v_W_mps - truth.v_W_S).norm());
    error.max_attitude_deg =
        std::max(error.max_attitude_deg,
                 logSO3(toQuaternion(s.q_wxyz).conjugate() * truth.q_W_S).norm() * 180.0 / std::numbers::pi);
  }
  return error;
}

/// 5 s of ideal 200 Hz IMU from `begin_ns` integrated with both interpolations; asserts the cubic one.
void expectIntegrationReproducesSpline(const TrajectoryFit& fit, std::int64_t begin_ns, const char* label) {
  ImuSimOptions options = idealImu();
  options.t_begin_ns = begin_ns;
  options.t_end_ns = begin_ns + 5 * kNsPerSecond;
  const ImuSimResult imu = simulateImu(fit.spline_W_S, options);
  ASSERT_EQ(imu.samples.size(), 1001u);
  const IntegrationError linear = integrateAgainstTruth(imu, Interpolation::kLinear);
  const IntegrationError cubic = integrateAgainstTruth(imu, Interpolation::kCubic);
  std::printf("  %-30s RK4 + cubic:  %.2e mm, %.2e deg, %.2e m/s | RK4 + linear: %.3f mm, %.2e deg, %.2e m/s\n", label,
              cubic.max_position_mm, cubic.max_attitude_deg, cubic.max_velocity_mps, linear.max_position_mm,
              linear.max_attitude_deg, linear.max_velocity_mps);
  EXPECT_LT(cubic.max_position_mm, 1.0) << label;
  EXPECT_LT(cubic.max_attitude_deg, 0.01) << label;
}

TEST(ImuSimulator, IdealImuIntegratesBackToTheLivingRoom0Spline) {
  const TrajectoryFit fit = fitTrajectory(test::readIclNuim(0), test::exampleT_S_C());
  for (const double begin_s : {0.0, 17.0, 40.0}) {
    const std::string label = "living_room_0 from " + std::to_string(static_cast<int>(begin_s)) + " s";
    expectIntegrationReproducesSpline(fit, fit.spline_W_S.startTimeNs() + secondsToNs(begin_s), label.c_str());
  }
}

TEST(ImuSimulator, IdealImuIntegratesBackToTheFastPresetSpline) {
  const TrajectoryFit fit = fitTrajectory(presetCameraPoses("fast"), test::exampleT_S_C());
  for (const double begin_s : {0.0, 5.0, 12.0}) {
    const std::string label = "fast from " + std::to_string(static_cast<int>(begin_s)) + " s";
    expectIntegrationReproducesSpline(fit, secondsToNs(begin_s), label.c_str());
  }
}

TEST(ImuSimulator, IdealImuMeasuresTheSplineKinematics) {
  const TrajectoryFit fit = fitTrajectory(presetCameraPoses("fast"), SE3d());
  const ImuSimResult imu = simulateImu(fit.spline_W_S, idealImu());
  ASSERT_EQ(imu.samples.size(), imu.states.size());
  ASSERT_EQ(imu.samples.size(), 4001u);  // 20 s at 200 Hz, both ends included
  for (std::size_t k = 0; k < imu.samples.size(); k += 97) {
    EXPECT_EQ(imu.samples[k].t_ns, static_cast<std::int64_t>(k) * 5'000'000);
    const Se3Spline::Kinematics kin = fit.spline_W_S.kinematics(imu.samples[k].t_ns);
    EXPECT_MATRIX_NEAR(imu.samples[k].gyro_rad_s, kin.omega_S_rad_s, 1e-12);
    EXPECT_MATRIX_NEAR(imu.samples[k].accel_mps2, kin.T_W_S.quaternion().conjugate() * (kin.a_W_mps2 - kG_W_mps2),
                       1e-12);
    EXPECT_MATRIX_NEAR(imu.states[k].p_W_S, kin.T_W_S.translation(), 0.0);
    EXPECT_MATRIX_NEAR(imu.states[k].v_W_S, kin.v_W_mps, 0.0);
    EXPECT_EQ(imu.states[k].b_g, Eigen::Vector3d::Zero());
    EXPECT_EQ(imu.states[k].b_a, Eigen::Vector3d::Zero());
  }
  EXPECT_EQ(imu.gyro_clipped_samples, 0);
  EXPECT_EQ(imu.accel_clipped_samples, 0);
}

TEST(ImuSimulator, AtRestTheAccelerometerReadsGravityUp) {
  // S rotated 90° about x: the world's up axis (+y) is the sensor's −z axis.
  const Eigen::Quaterniond q_W_S(Eigen::AngleAxisd(std::numbers::pi / 2.0, Eigen::Vector3d::UnitX()));
  const ImuSimResult imu = simulateImu(staticSpline(q_W_S, 2.0), idealImu());
  for (const ImuSample& s : imu.samples) {
    EXPECT_MATRIX_NEAR(s.accel_mps2, Eigen::Vector3d(0.0, 0.0, -9.81), 1e-12);
    EXPECT_MATRIX_NEAR(s.gyro_rad_s, Eigen::Vector3d::Zero(), 1e-12);
  }
}

TEST(ImuSimulator, WhiteNoiseHasTheDiscreteStandardDeviation) {
  const TrajectoryFit fit = fitTrajectory(presetCameraPoses("long"), SE3d());
  ImuSimOptions noisy = idealImu();
  noisy.add_noise = true;
  noisy.seed = 7;
  const ImuSimResult truth = simulateImu(fit.spline_W_S, idealImu());
  const ImuSimResult measured = simulateImu(fit.spline_W_S, noisy);
  ASSERT_EQ(truth.samples.size(), measured.samples.size());
  const double n = static_cast<double>(truth.samples.size());  // 12001 samples: σ estimated to ±0.65 % (1σ)

  Eigen::Array3d sum_g = Eigen::Array3d::Zero(), sum_sq_g = Eigen::Array3d::Zero();
  Eigen::Array3d sum_a = Eigen::Array3d::Zero(), sum_sq_a = Eigen::Array3d::Zero();
  for (std::size_t k = 0; k < truth.samples.size(); ++k) {
    const Eigen::Array3d e_g = measured.samples[k].gyro_rad_s - truth.samples[k].gyro_rad_s;
    const Eigen::Array3d e_a = measured.samples[k].accel_mps2 - truth.samples[k].accel_mps2;
    sum_g += e_g;
    sum_sq_g += e_g.square();
    sum_a += e_a;
    sum_sq_a += e_a.square();
  }
  const double sqrt_rate = std::sqrt(noisy.noise.rate_hz);
  const double sigma_g = noisy.noise.gyro_noise_density * sqrt_rate;   // 0.017 rad/s
  const double sigma_a = noisy.noise.accel_noise_density * sqrt_rate;  // 0.113 m/s²
  const Eigen::Array3d std_g = (sum_sq_g / n - (sum_g / n).square()).sqrt();
  const Eigen::Array3d std_a = (sum_sq_a / n - (sum_a / n).square()).sqrt();
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_NEAR(std_g[axis] / sigma_g, 1.0, 0.03) << "gyro axis " << axis;
    EXPECT_NEAR(std_a[axis] / sigma_a, 1.0, 0.03) << "accel axis " << axis;
    EXPECT_NEAR(sum_g[axis] / n, 0.0, 4.0 * sigma_g / std::sqrt(n));
    EXPECT_NEAR(sum_a[axis] / n, 0.0, 4.0 * sigma_a / std::sqrt(n));
  }
}

TEST(ImuSimulator, BiasesStartAtThePriorAndRandomWalk) {
  // 400 seeds × 10 s at rest: the initial biases' spread is the prior, and over a lag τ the random part
  // changes with variance σ_b²·τ (checked for τ = 1 s and 5 s from non-overlapping windows). At 20 Hz rather
  // than 200 Hz: the law must not depend on the rate, and the test stays fast in debug builds.
  ImuSimOptions options = idealImu();
  options.add_biases = true;
  options.noise = ImuNoiseParams::zr300();  // has a static accelerometer bias, to check it is reported
  options.noise.rate_hz = 20.0;
  const Se3Spline spline = staticSpline(Eigen::Quaterniond::Identity(), 10.0);
  constexpr int kSeeds = 400;
  constexpr int kSamplesPerSecond = 20;
  double sum_sq_initial_g = 0.0, sum_sq_initial_a = 0.0;
  std::array<double, 2> sum_sq_walk_g{}, sum_sq_walk_a{};
  std::array<int, 2> walk_count{};
  constexpr std::array<int, 2> kLags_s{1, 5};
  for (int seed = 0; seed < kSeeds; ++seed) {
    options.seed = static_cast<std::uint64_t>(seed);
    const ImuSimResult imu = simulateImu(spline, options);
    ASSERT_EQ(imu.states.size(), 201u);
    const Eigen::Vector3d random_b_a0 = imu.states[0].b_a - options.noise.static_accel_bias_mps2;
    sum_sq_initial_g += imu.states[0].b_g.squaredNorm();
    sum_sq_initial_a += random_b_a0.squaredNorm();
    // The reported bias is the one in the measurement (static part included).
    EXPECT_MATRIX_NEAR(imu.samples[50].gyro_rad_s, imu.states[50].b_g, 1e-12);
    EXPECT_MATRIX_NEAR(imu.samples[50].accel_mps2 - Eigen::Vector3d(0.0, 9.81, 0.0), imu.states[50].b_a, 1e-12);
    for (std::size_t lag = 0; lag < kLags_s.size(); ++lag) {
      const int step = kLags_s[lag] * kSamplesPerSecond;
      for (int k = 0; k + step < static_cast<int>(imu.states.size()); k += step) {
        sum_sq_walk_g[lag] += (imu.states[k + step].b_g - imu.states[k].b_g).squaredNorm();
        sum_sq_walk_a[lag] += (imu.states[k + step].b_a - imu.states[k].b_a).squaredNorm();
        walk_count[lag] += 3;
      }
    }
  }
  const double axes = 3.0 * kSeeds;  // 1200 values: σ estimated to ±2 % (1σ)
  EXPECT_NEAR(std::sqrt(sum_sq_initial_g / axes) / options.noise.gyro_bias_prior, 1.0, 0.07);
  EXPECT_NEAR(std::sqrt(sum_sq_initial_a / axes) / options.noise.accel_bias_prior, 1.0, 0.07);
  for (std::size_t lag = 0; lag < kLags_s.size(); ++lag) {
    const double tau_s = kLags_s[lag];
    const double expected_g = options.noise.gyro_random_walk * options.noise.gyro_random_walk * tau_s;
    const double expected_a = options.noise.accel_random_walk * options.noise.accel_random_walk * tau_s;
    // 24000 (τ = 1 s) and 4800 (τ = 5 s) increments: variance to ±0.9 % and ±2 % (1σ).
    EXPECT_NEAR(sum_sq_walk_g[lag] / walk_count[lag] / expected_g, 1.0, 0.06) << "τ = " << tau_s << " s";
    EXPECT_NEAR(sum_sq_walk_a[lag] / walk_count[lag] / expected_a, 1.0, 0.06) << "τ = " << tau_s << " s";
  }
}

TEST(ImuSimulator, SaturationClampsEachAxisAndIsCounted) {
  // A constant 10 rad/s turn about S's z axis (beyond the 7.8 rad/s limit) on a 0.1 s-knot spline.
  std::vector<Eigen::Vector3d> p_W_m(30, Eigen::Vector3d::Zero());
  std::vector<Eigen::Quaterniond> q_W_S{Eigen::Quaterniond::Identity()};
  for (int i = 1; i < 30; ++i) q_W_S.push_back(q_W_S.back() * expSO3(Eigen::Vector3d(0.0, 0.0, 1.0)));
  const Se3Spline spinning(0, 100'000'000, p_W_m, q_W_S);
  ImuSimOptions options = idealImu();
  // Gravity turns in S's x-y plane, so the larger of |f_x|, |f_y| swings between 9.81/√2 = 6.9 and 9.81 m/s²:
  // an 8 m/s² limit clips part of the samples.
  options.noise.accel_saturation_mps2 = 8.0;
  const ImuSimResult imu = simulateImu(spinning, options);
  EXPECT_EQ(imu.gyro_clipped_samples, static_cast<std::int64_t>(imu.samples.size()));
  for (const ImuSample& s : imu.samples) {
    EXPECT_DOUBLE_EQ(s.gyro_rad_s.z(), 7.8);
    EXPECT_LE(s.accel_mps2.cwiseAbs().maxCoeff(), 8.0);
  }
  EXPECT_GT(imu.accel_clipped_samples, 0);
  EXPECT_LT(imu.accel_clipped_samples, static_cast<std::int64_t>(imu.samples.size()));
}

TEST(ImuSimulator, SameSeedSameDataOtherSeedOtherData) {
  const TrajectoryFit fit = fitTrajectory(presetCameraPoses("white_wall"), SE3d());
  ImuSimOptions options;
  options.seed = 42;
  const ImuSimResult a = simulateImu(fit.spline_W_S, options);
  const ImuSimResult b = simulateImu(fit.spline_W_S, options);
  options.seed = 43;
  const ImuSimResult c = simulateImu(fit.spline_W_S, options);
  ASSERT_EQ(a.samples.size(), b.samples.size());
  ASSERT_EQ(a.samples.size(), c.samples.size());
  std::size_t differing = 0;
  for (std::size_t k = 0; k < a.samples.size(); ++k) {
    EXPECT_EQ(a.samples[k].gyro_rad_s, b.samples[k].gyro_rad_s);
    EXPECT_EQ(a.samples[k].accel_mps2, b.samples[k].accel_mps2);
    EXPECT_EQ(a.states[k].b_g, b.states[k].b_g);
    EXPECT_EQ(a.states[k].b_a, b.states[k].b_a);
    differing += (a.samples[k].gyro_rad_s != c.samples[k].gyro_rad_s) ? 1 : 0;
  }
  EXPECT_EQ(differing, a.samples.size());
  // Switching noise off leaves the biases of the same seed unchanged (fixed draw order).
  options.seed = 42;
  options.add_noise = false;
  const ImuSimResult quiet = simulateImu(fit.spline_W_S, options);
  EXPECT_EQ(quiet.states.back().b_g, a.states.back().b_g);
  EXPECT_EQ(quiet.states.back().b_a, a.states.back().b_a);
}

TEST(ImuSimulator, RejectsInconsistentOptions) {
  const Se3Spline spline = staticSpline(Eigen::Quaterniond::Identity(), 3.0);
  ImuSimOptions options;
  options.g_W_mps2 = Eigen::Vector3d(0.0, 0.0, -9.80665);
  EXPECT_THROW(simulateImu(spline, options), Error);
  options = {};
  options.t_end_ns = spline.endTimeNs() + 1;
  EXPECT_THROW(simulateImu(spline, options), Error);
  options = {};
  options.noise.rate_hz = 0.0;
  EXPECT_THROW(simulateImu(spline, options), Error);
}

}  // namespace
}  // namespace vifusion::sim
