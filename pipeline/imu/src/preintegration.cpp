#include "vifusion/imu/preintegration.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "vifusion/core/so3.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion::imu {
namespace {

constexpr int kP = kDeltaIdxP;
constexpr int kPhi = kDeltaIdxPhi;
constexpr int kV = kDeltaIdxV;
constexpr int kBg = kDeltaIdxBg;
constexpr int kBa = kDeltaIdxBa;

/// Gyro and accelerometer readings at one instant.
struct Reading {
  Eigen::Vector3d gyro_rad_s;
  Eigen::Vector3d accel_mps2;
};

/// The reading at t_ns on the straight line between samples a and b (a.t_ns ≤ t_ns ≤ b.t_ns).
Reading interpolate(const ImuSample& a, const ImuSample& b, std::int64_t t_ns) {
  const double w = static_cast<double>(t_ns - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns);
  return {a.gyro_rad_s + w * (b.gyro_rad_s - a.gyro_rad_s), a.accel_mps2 + w * (b.accel_mps2 - a.accel_mps2)};
}

bool atLimit(const Eigen::Vector3d& reading, double limit) { return reading.cwiseAbs().maxCoeff() >= limit; }

/// covariance⁻¹ through a Jacobi-scaled Cholesky factorisation: the diagonal spans ~1e-13 (bias walk over
/// one frame) to ~1e-6 (rotation), and scaling to unit diagonal keeps the factorisation well conditioned.
Matrix15d inverseCovariance(const Matrix15d& covariance) {
  const Eigen::Matrix<double, kDeltaDim, 1> scale = covariance.diagonal().cwiseSqrt().cwiseInverse();
  const Matrix15d correlation = scale.asDiagonal() * covariance * scale.asDiagonal();
  const Matrix15d inverse_correlation = correlation.llt().solve(Matrix15d::Identity());
  return scale.asDiagonal() * inverse_correlation * scale.asDiagonal();
}

/// The running sums of one integration.
class Integration {
 public:
  Integration(const ImuOptions& options, const Eigen::Vector3d& b_g_lin_rad_s, const Eigen::Vector3d& b_a_lin_mps2)
      : options_(options), b_g_lin_rad_s_(b_g_lin_rad_s), b_a_lin_mps2_(b_a_lin_mps2) {}

  /// One mid-point step of h_s [s] between readings `begin` and `end`.
  void step(const Reading& begin, const Reading& end, double h_s, bool gyro_saturated, bool accel_saturated) {
    const Eigen::Vector3d omega_rad_s = 0.5 * (begin.gyro_rad_s + end.gyro_rad_s) - b_g_lin_rad_s_;
    const Eigen::Vector3d accel_mps2 = 0.5 * (begin.accel_mps2 + end.accel_mps2) - b_a_lin_mps2_;
    const Eigen::Vector3d theta_rad = omega_rad_s * h_s;
    const Eigen::Quaterniond q_step = expSO3(theta_rad);
    const Eigen::Matrix3d R_half = expSO3(0.5 * theta_rad).toRotationMatrix();
    const Eigen::Matrix3d R_mid = q_S0_S_.toRotationMatrix() * R_half;  // R_S0_S at the step's middle
    const Eigen::Matrix3d R_mid_a_hat = R_mid * hat(accel_mps2);
    const Eigen::Vector3d accel_S0_mps2 = R_mid * accel_mps2;

    // Error-state transition over η, the bias parts being errors u added to both mean readings:
    // δ(R_mid·â) = −R_mid·[â]×·(R_halfᵀ·δφ + ½h·J_r(½θ)·u_g) + R_mid·u_a.
    const Eigen::Matrix3d d_mid_d_phi = -R_mid_a_hat * R_half.transpose();
    const Eigen::Matrix3d d_mid_d_ug = -R_mid_a_hat * (0.5 * h_s) * rightJacobianSO3(0.5 * theta_rad);
    Matrix15d F = Matrix15d::Identity();
    F.block<3, 3>(kP, kPhi) = 0.5 * h_s * h_s * d_mid_d_phi;
    F.block<3, 3>(kP, kV) = h_s * Eigen::Matrix3d::Identity();
    F.block<3, 3>(kP, kBg) = 0.5 * h_s * h_s * d_mid_d_ug;
    F.block<3, 3>(kP, kBa) = 0.5 * h_s * h_s * R_mid;
    F.block<3, 3>(kPhi, kPhi) = q_step.toRotationMatrix().transpose();
    F.block<3, 3>(kPhi, kBg) = h_s * rightJacobianSO3(theta_rad);
    F.block<3, 3>(kV, kPhi) = h_s * d_mid_d_phi;
    F.block<3, 3>(kV, kBg) = h_s * d_mid_d_ug;
    F.block<3, 3>(kV, kBa) = h_s * R_mid;

    // A bias increase lowers both readings by the same amount, so the bias Jacobians follow the error
    // state with the bias columns negated.
    d_delta_d_bias_ = F.topLeftCorner<9, 9>() * d_delta_d_bias_ - F.topRightCorner<9, 6>();

    // Gyro white noise enters like u_g; its discrete variance on the step's mean reading is σ²/h.
    const NoiseVariances var = noiseVariances(gyro_saturated, accel_saturated);
    const Eigen::Matrix<double, 9, 3> G_gyro = F.block<9, 3>(0, kBg);
    Matrix15d Q = Matrix15d::Zero();
    Q.topLeftCorner<9, 9>() = var.gyro / h_s * G_gyro * G_gyro.transpose();
    Q.block<3, 3>(kV, kV).diagonal().array() += var.accel * h_s;
    Q.block<3, 3>(kP, kV).diagonal().array() += var.accel * h_s * h_s / 2.0;
    Q.block<3, 3>(kV, kP).diagonal().array() += var.accel * h_s * h_s / 2.0;
    Q.block<3, 3>(kP, kP).diagonal().array() += var.accel * h_s * h_s * h_s / 3.0;
    Q.block<3, 3>(kBg, kBg).diagonal().array() += var.gyro_walk * h_s;
    Q.block<3, 3>(kBa, kBa).diagonal().array() += var.accel_walk * h_s;
    covariance_ = F * covariance_ * F.transpose() + Q;

    dp_S0_m_ += h_s * dv_S0_mps_ + 0.5 * h_s * h_s * accel_S0_mps2;
    dv_S0_mps_ += h_s * accel_S0_mps2;
    q_S0_S_ = (q_S0_S_ * q_step).normalized();
    gyro_saturated_steps_ += gyro_saturated ? 1 : 0;
    accel_saturated_steps_ += accel_saturated ? 1 : 0;
  }

  void finish(PreintegratedImu& out) const {
    out.b_g_lin_rad_s = b_g_lin_rad_s_;
    out.b_a_lin_mps2 = b_a_lin_mps2_;
    out.delta = {q_S0_S_, dv_S0_mps_, dp_S0_m_};
    out.d_R_d_bg = d_delta_d_bias_.block<3, 3>(kPhi, 0);
    out.d_v_d_bg = d_delta_d_bias_.block<3, 3>(kV, 0);
    out.d_v_d_ba = d_delta_d_bias_.block<3, 3>(kV, 3);
    out.d_p_d_bg = d_delta_d_bias_.block<3, 3>(kP, 0);
    out.d_p_d_ba = d_delta_d_bias_.block<3, 3>(kP, 3);
    out.covariance = 0.5 * (covariance_ + covariance_.transpose());
    out.information = inverseCovariance(out.covariance);
    out.gyro_saturated_steps = gyro_saturated_steps_;
    out.accel_saturated_steps = accel_saturated_steps_;
    out.reintegrate_above_rad = options_.reintegrate_above_rad;
  }

 private:
  /// Per-axis continuous variances [σ²], white noise inflated where the step touches a saturated sample.
  struct NoiseVariances {
    double gyro;        ///< [(rad/s)²/Hz]
    double accel;       ///< [(m/s²)²/Hz]
    double gyro_walk;   ///< [(rad/s²)²/Hz]
    double accel_walk;  ///< [(m/s³)²/Hz]
  };

  NoiseVariances noiseVariances(bool gyro_saturated, bool accel_saturated) const {
    const ImuNoiseParams& n = options_.noise;
    const double inflation = options_.saturation_noise_factor * options_.saturation_noise_factor;
    return {n.gyro_noise_density * n.gyro_noise_density * (gyro_saturated ? inflation : 1.0),
            n.accel_noise_density * n.accel_noise_density * (accel_saturated ? inflation : 1.0),
            n.gyro_random_walk * n.gyro_random_walk, n.accel_random_walk * n.accel_random_walk};
  }

  const ImuOptions& options_;
  Eigen::Vector3d b_g_lin_rad_s_;
  Eigen::Vector3d b_a_lin_mps2_;
  Eigen::Quaterniond q_S0_S_ = Eigen::Quaterniond::Identity();
  Eigen::Vector3d dv_S0_mps_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d dp_S0_m_ = Eigen::Vector3d::Zero();
  Eigen::Matrix<double, 9, 6> d_delta_d_bias_ = Eigen::Matrix<double, 9, 6>::Zero();  ///< ∂[Δp, Δφ, Δv]/∂[b_g, b_a]
  Matrix15d covariance_ = Matrix15d::Zero();
  int gyro_saturated_steps_ = 0;
  int accel_saturated_steps_ = 0;
};

}  // namespace

ImuDeltas PreintegratedImu::corrected(const Eigen::Vector3d& b_g_rad_s, const Eigen::Vector3d& b_a_mps2) const {
  const Eigen::Vector3d d_bg = b_g_rad_s - b_g_lin_rad_s;
  const Eigen::Vector3d d_ba = b_a_mps2 - b_a_lin_mps2;
  return {(delta.q_S0_S1 * expSO3(d_R_d_bg * d_bg)).normalized(), delta.dv_S0_mps + d_v_d_bg * d_bg + d_v_d_ba * d_ba,
          delta.dp_S0_m + d_p_d_bg * d_bg + d_p_d_ba * d_ba};
}

bool PreintegratedImu::needsReintegration(const Eigen::Vector3d& b_g_rad_s) const {
  return (b_g_rad_s - b_g_lin_rad_s).norm() * dt_s > reintegrate_above_rad;
}

ImuPreintegrator::ImuPreintegrator(const ImuOptions& options) : options_(options), max_gap_ns_(0) {
  options_.validate();
  max_gap_ns_ = options_.maxGapNs();
}

std::optional<ImuSampleIssue> ImuPreintegrator::integrate(std::span<const ImuSample> samples, std::int64_t t0_ns,
                                                          std::int64_t t1_ns, const Eigen::Vector3d& b_g_lin_rad_s,
                                                          const Eigen::Vector3d& b_a_lin_mps2,
                                                          PreintegratedImu& out) const {
  SampleRange range;
  if (auto issue = checkSampleWindow(samples, t0_ns, t1_ns, max_gap_ns_, range)) return issue;

  const double gyro_limit = options_.noise.gyro_saturation_rad_s;
  const double accel_limit = options_.noise.accel_saturation_mps2;
  Integration integration(options_, b_g_lin_rad_s, b_a_lin_mps2);
  // Every sample interval [t_k, t_k+1] of the range overlaps (t0, t1) by a positive length: the range
  // starts at the last sample ≤ t0 and ends at the first ≥ t1, and the stamps increase strictly.
  for (std::size_t k = range.first; k < range.last; ++k) {
    const ImuSample& a = samples[k];
    const ImuSample& b = samples[k + 1];
    const std::int64_t begin_ns = std::max(a.t_ns, t0_ns);
    const std::int64_t end_ns = std::min(b.t_ns, t1_ns);
    integration.step(interpolate(a, b, begin_ns), interpolate(a, b, end_ns), nsToSeconds(end_ns - begin_ns),
                     atLimit(a.gyro_rad_s, gyro_limit) || atLimit(b.gyro_rad_s, gyro_limit),
                     atLimit(a.accel_mps2, accel_limit) || atLimit(b.accel_mps2, accel_limit));
  }
  out.t0_ns = t0_ns;
  out.t1_ns = t1_ns;
  out.dt_s = nsToSeconds(t1_ns - t0_ns);
  integration.finish(out);
  return std::nullopt;
}

}  // namespace vifusion::imu
