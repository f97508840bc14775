#pragma once
// IMU preintegration between two frame times t0_ns < t1_ns (Forster, Carlone, Dellaert, Scaramuzza,
// "On-Manifold Preintegration for Real-Time Visual-Inertial Odometry", T-RO 2017; GTSAM's
// ManifoldPreintegration), as the paper extends OKVIS's error term with it (§IV-C).
//
// CONVENTION of the whole library (stated here once): Forster/GTSAM-style deltas, not OKVIS's.
//  - Biases are held at a linearisation point b_g_lin [rad/s], b_a_lin [m/s²]; ω̂ = ω̃ − b_g_lin [rad/s],
//    â = ã − b_a_lin [m/s²] with ω̃, ã the readings in S (sensor_data.hpp). Δt = t1 − t0 [s].
//  - ΔR = R_S0_S1: orientation of S at t1 in S at t0 (rotates S1 vectors into S0).
//    Δv = ∫ R_S0_S(t)·â(t) dt [m/s] and Δp = ∬ R_S0_S(t)·â(t) dt² [m], both in S0, gravity NOT included.
//  - Gravity points DOWN and is ADDED (GTSAM, Basalt; OKVIS subtracts an up-vector): in the inertial frame I,
//    g_I = (0, 0, −g) [m/s²] with g = ImuNoiseParams::gravity_mps2, and for S's pose and velocity in I
//      R_I_S1 = R_I_S0·ΔR,   v_I_S1 = v_I_S0 + g_I·Δt + R_I_S0·Δv,
//      p_I_S1 = p_I_S0 + v_I_S0·Δt + ½·g_I·Δt² + R_I_S0·Δp.
//  - Rotation perturbations of the deltas are on the RIGHT, in S1 (Forster): a bias change δb = b − b_lin
//    gives ΔR(b) ≈ ΔR·Exp(∂ΔR/∂b_g·δb_g), noise δφ [rad] is ΔR_measured = ΔR_true·Exp(δφ). The state
//    (state.hpp) perturbs on the LEFT; imu_error.hpp converts between the two.
//  - First-order bias correction: ΔR ← ΔR·Exp(∂ΔR/∂b_g·δb_g), Δv ← Δv + ∂Δv/∂b_g·δb_g + ∂Δv/∂b_a·δb_a,
//    Δp likewise. Δv and Δp are exactly linear in b_a (it never touches the rotation), so only b_g's change
//    can outgrow the correction: once ‖δb_g‖·Δt > ImuOptions::reintegrate_above_rad (1e-4 rad, OKVIS's
//    rule) the caller re-integrates at the new biases (needsReintegration()). At the threshold, with a
//    0.01 m/s² accelerometer-bias change as well, the neglected second-order terms measured 5e-11 rad,
//    2e-10 m and 2e-8 m/s over a 30 Hz frame (tests/unit/imu), far under that frame's white noise
//    (σ_g·√Δt ≈ 2e-4 rad, σ_a·√Δt ≈ 1.5e-3 m/s); a frame holds ~7 samples, so re-integrating is cheap
//    and the rule can afford to be this strict.
//  - Integration: the readings are linearly interpolated to t0 and t1; between consecutive grid points
//    (t0, every sample inside, t1) ω̂ and â are the means of the two ends, R_{k+1} = R_k·Exp(ω̂h), and â is
//    rotated with the mid-point R_k·Exp(½ω̂h) (Basalt's rule; second-order accurate, where GTSAM's Euler
//    step with R_k is first-order). The bias Jacobians are the exact derivatives of this discrete scheme.
//  - Covariance of η = [δp, δφ, δv, δb_g, δb_a] (δb_g, δb_a: the bias random walk from t0 to t1; the same
//    index order as the first 15 entries of state.hpp's δx), propagated per step as P ← F·P·Fᵀ + Q from the
//    continuous densities σ of ImuNoiseParams: white noise of a step's mean reading has the discrete
//    variance σ²/h (Kalibr, Forster), so the gyro adds σ_g²·h·J_r·J_rᵀ to δφ; the accelerometer adds the
//    exact continuous kernel σ_a²·[h, h²/2; h²/2, h³/3] to (δv, δp) (isotropic, so the rotation drops out;
//    one held sample would give h³/4 and a singular covariance after a single step); the biases walk by
//    σ_b²·h and, as errors of both mean readings, couple into δφ, δv, δp through F (GTSAM's
//    CombinedImuFactor does the same), so the error term gets their cross-covariance too. A step with a saturated
//    sample at either end has its white-noise σ scaled by ImuOptions::saturation_noise_factor.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <span>

#include "vifusion/core/sensor_data.hpp"
#include "vifusion/imu/imu_options.hpp"
#include "vifusion/imu/sample_window.hpp"

namespace vifusion::imu {

/// Indices into the preintegration error η (the same positions as state.hpp's δx).
inline constexpr int kDeltaDim = 15;
inline constexpr int kDeltaIdxP = 0;    ///< δp [m], in S0
inline constexpr int kDeltaIdxPhi = 3;  ///< δφ [rad], right perturbation of ΔR, in S1
inline constexpr int kDeltaIdxV = 6;    ///< δv [m/s], in S0
inline constexpr int kDeltaIdxBg = 9;   ///< gyro bias walk b_g(t1) − b_g(t0) [rad/s]
inline constexpr int kDeltaIdxBa = 12;  ///< accelerometer bias walk b_a(t1) − b_a(t0) [m/s²]

using Matrix15d = Eigen::Matrix<double, kDeltaDim, kDeltaDim>;

/// The three deltas of the convention above.
struct ImuDeltas {
  Eigen::Quaterniond q_S0_S1 = Eigen::Quaterniond::Identity();  ///< ΔR: rotates S1 vectors into S0
  Eigen::Vector3d dv_S0_mps = Eigen::Vector3d::Zero();          ///< Δv in S0, gravity-free [m/s]
  Eigen::Vector3d dp_S0_m = Eigen::Vector3d::Zero();            ///< Δp in S0, gravity-free [m]
};

/// One frame interval's preintegrated measurements. Fixed size: no heap memory.
struct PreintegratedImu {
  std::int64_t t0_ns = 0;
  std::int64_t t1_ns = 0;
  double dt_s = 0.0;                                        ///< t1 − t0 [s]
  Eigen::Vector3d b_g_lin_rad_s = Eigen::Vector3d::Zero();  ///< gyro bias held during integration [rad/s]
  Eigen::Vector3d b_a_lin_mps2 = Eigen::Vector3d::Zero();   ///< accelerometer bias held [m/s²]
  ImuDeltas delta;                                          ///< at the linearisation biases
  Eigen::Matrix3d d_R_d_bg = Eigen::Matrix3d::Zero();       ///< ∂ΔR/∂b_g, right-perturbation [rad/(rad/s)] = [s]
  Eigen::Matrix3d d_v_d_bg = Eigen::Matrix3d::Zero();       ///< ∂Δv/∂b_g [(m/s)/(rad/s)]
  Eigen::Matrix3d d_v_d_ba = Eigen::Matrix3d::Zero();       ///< ∂Δv/∂b_a [s]
  Eigen::Matrix3d d_p_d_bg = Eigen::Matrix3d::Zero();       ///< ∂Δp/∂b_g [m/(rad/s)]
  Eigen::Matrix3d d_p_d_ba = Eigen::Matrix3d::Zero();       ///< ∂Δp/∂b_a [s²]
  Matrix15d covariance = Matrix15d::Zero();                 ///< of η = [δp, δφ, δv, δb_g, δb_a] (SI units)
  Matrix15d information = Matrix15d::Zero();                ///< covariance⁻¹
  int gyro_saturated_steps = 0;        ///< integration steps down-weighted for a gyro reading at its limit
  int accel_saturated_steps = 0;       ///< same for the accelerometer
  double reintegrate_above_rad = 0.0;  ///< ImuOptions::reintegrate_above_rad at integration [rad]

  /// The deltas corrected to first order for biases b_g [rad/s], b_a [m/s²].
  ImuDeltas corrected(const Eigen::Vector3d& b_g_rad_s, const Eigen::Vector3d& b_a_mps2) const;
  /// True when ‖b_g − b_g_lin‖·Δt exceeds the threshold: integrate again with these biases.
  bool needsReintegration(const Eigen::Vector3d& b_g_rad_s) const;
};

class ImuPreintegrator {
 public:
  /// @throws vifusion::Error from options.validate().
  explicit ImuPreintegrator(const ImuOptions& options);

  const ImuOptions& options() const { return options_; }

  /// Checks the samples (sample_window.hpp) and integrates them over [t0_ns, t1_ns] with the biases held
  /// at b_g_lin [rad/s], b_a_lin [m/s²] into `out`. Returns the first problem found instead, leaving `out`
  /// untouched. Allocates nothing.
  [[nodiscard]] std::optional<ImuSampleIssue> integrate(std::span<const ImuSample> samples, std::int64_t t0_ns,
                                                        std::int64_t t1_ns, const Eigen::Vector3d& b_g_lin_rad_s,
                                                        const Eigen::Vector3d& b_a_lin_mps2,
                                                        PreintegratedImu& out) const;

 private:
  ImuOptions options_;
  std::int64_t max_gap_ns_;
};

}  // namespace vifusion::imu
