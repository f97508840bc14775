#pragma once
// IMU measurements from an IMU-body spline (algorithms.md §3; Nikolic et al. 2016 / Kalibr noise model):
//
//   gyro  = ω_S(t) + b_g + n_g
//   accel = R_W_S(t)ᵀ·(a_W(t) − g_W) + b_a + b_static + n_a        (at rest: +|g| on the up axis)
//
// per axis, then clamped to ±saturation. Discretised at rate f: n ~ N(0, (σ·√f)²) per sample; the random
// biases start at N(0, prior²) and walk b ← b + σ_b/√f·N(0, 1) after each sample. Samples are at
// t_k = t_begin + round(k·10⁹/f) ns up to t_end.
//
// The spline is the IMU body's own (TrajectoryFit::spline_W_S), so no lever-arm terms arise and T_S_C is not
// needed here: ω and the specific force are those of S by construction.
//
// Random numbers: one NormalRng stream per seed, drawn in a fixed order (6 for the initial biases, then 12 per
// sample: gyro noise, accel noise, gyro walk, accel walk), always drawn even when a term is switched off, so
// the biases of a run with noise off equal those of the same seed with noise on.

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

#include "vifusion/core/imu_noise.hpp"
#include "vifusion/core/sensor_data.hpp"
#include "vifusion/sim/se3_spline.hpp"

namespace vifusion::sim {

struct ImuSimOptions {
  ImuNoiseParams noise;  ///< densities, bias priors and walks, saturation, rate_hz (Table I synthetic default)
  /// Gravity in the spline's world [m/s²]; y-up worlds (ICL-NUIM) have (0, −9.81, 0). Its norm must equal
  /// noise.gravity_mps2, the value the estimator will assume.
  Eigen::Vector3d g_W_mps2 = Eigen::Vector3d(0.0, -9.81, 0.0);
  std::uint64_t seed = 0;
  bool add_noise = true;   ///< white noise n_g, n_a
  bool add_biases = true;  ///< initial random biases, their random walk and the static accelerometer bias
  std::optional<std::int64_t> t_begin_ns;  ///< first sample; default: the spline's start
  std::optional<std::int64_t> t_end_ns;    ///< no sample after this; default: the spline's end
};

struct ImuSimResult {
  std::vector<ImuSample> samples;          ///< what the IMU reports
  std::vector<GroundTruthState> states;    ///< truth at each sample: pose and velocity of S, the biases in
                                           ///< effect (b_a includes the static accelerometer bias)
  std::int64_t gyro_clipped_samples = 0;   ///< samples with at least one gyro axis at the saturation limit
  std::int64_t accel_clipped_samples = 0;  ///< same for the accelerometer
};

/// @throws vifusion::Error if the noise parameters are invalid, |g_W| ≠ noise.gravity_mps2, or the time range
///         is empty or outside the spline.
ImuSimResult simulateImu(const Se3Spline& spline_W_S, const ImuSimOptions& options = {});

}  // namespace vifusion::sim
