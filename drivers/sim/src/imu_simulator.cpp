#include "vifusion/sim/imu_simulator.hpp"

#include <cmath>
#include <string>

#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/sim/normal_rng.hpp"

namespace vifusion::sim {
namespace {

Eigen::Vector3d normal3(NormalRng& rng) {
  // Named temporaries fix the draw order (argument evaluation order is unspecified).
  const double x = rng();
  const double y = rng();
  const double z = rng();
  return {x, y, z};
}

/// Clamps each axis to ±limit; true if any axis was clamped.
bool saturate(Eigen::Vector3d& v, double limit) {
  const Eigen::Vector3d clamped = v.cwiseMax(-limit).cwiseMin(limit);
  const bool clipped = clamped != v;
  v = clamped;
  return clipped;
}

}  // namespace

ImuSimResult simulateImu(const Se3Spline& spline_W_S, const ImuSimOptions& options) {
  const ImuNoiseParams& noise = options.noise;
  noise.validate();
  if (std::abs(options.g_W_mps2.norm() - noise.gravity_mps2) > 1e-9 * noise.gravity_mps2) {
    throw Error("simulateImu: |g_W| = " + std::to_string(options.g_W_mps2.norm()) +
                " m/s² differs from the IMU parameters' gravity_mps2 = " + std::to_string(noise.gravity_mps2));
  }
  const std::int64_t t_begin_ns = options.t_begin_ns.value_or(spline_W_S.startTimeNs());
  const std::int64_t t_end_ns = options.t_end_ns.value_or(spline_W_S.endTimeNs());
  if (t_begin_ns < spline_W_S.startTimeNs() || t_end_ns > spline_W_S.endTimeNs() || t_end_ns < t_begin_ns) {
    throw Error("simulateImu: time range [" + std::to_string(t_begin_ns) + ", " + std::to_string(t_end_ns) +
                "] ns is empty or leaves the spline's range [" + std::to_string(spline_W_S.startTimeNs()) + ", " +
                std::to_string(spline_W_S.endTimeNs()) + "] ns");
  }

  const double sqrt_rate = std::sqrt(noise.rate_hz);
  const double gyro_noise_rad_s = noise.gyro_noise_density * sqrt_rate;
  const double accel_noise_mps2 = noise.accel_noise_density * sqrt_rate;
  const double gyro_walk_rad_s = noise.gyro_random_walk / sqrt_rate;  // per sample
  const double accel_walk_mps2 = noise.accel_random_walk / sqrt_rate;

  NormalRng rng(options.seed);
  Eigen::Vector3d b_g_rad_s = noise.gyro_bias_prior * normal3(rng);
  Eigen::Vector3d b_a_mps2 = noise.accel_bias_prior * normal3(rng);
  if (!options.add_biases) {
    b_g_rad_s.setZero();
    b_a_mps2.setZero();
  }
  const Eigen::Vector3d static_bias_mps2 =
      options.add_biases ? noise.static_accel_bias_mps2 : Eigen::Vector3d::Zero().eval();

  ImuSimResult result;
  const auto period_count =
      static_cast<std::size_t>(std::floor(nsToSeconds(t_end_ns - t_begin_ns) * noise.rate_hz + 1e-9));
  result.samples.reserve(period_count + 1);
  result.states.reserve(period_count + 1);
  const double period_ns = static_cast<double>(kNsPerSecond) / noise.rate_hz;
  for (std::int64_t k = 0;; ++k) {
    // From k, not by accumulating a rounded period, so a non-integer period does not drift.
    const std::int64_t t_ns = t_begin_ns + static_cast<std::int64_t>(std::llround(static_cast<double>(k) * period_ns));
    if (t_ns > t_end_ns) break;
    const Se3Spline::Kinematics kin = spline_W_S.kinematics(t_ns);
    const Eigen::Vector3d n_g = normal3(rng);
    const Eigen::Vector3d n_a = normal3(rng);
    const Eigen::Vector3d w_g = normal3(rng);
    const Eigen::Vector3d w_a = normal3(rng);

    const Eigen::Vector3d b_a_total_mps2 = b_a_mps2 + static_bias_mps2;
    ImuSample sample;
    sample.t_ns = t_ns;
    sample.gyro_rad_s = kin.omega_S_rad_s + b_g_rad_s;
    sample.accel_mps2 = kin.T_W_S.quaternion().conjugate() * (kin.a_W_mps2 - options.g_W_mps2) + b_a_total_mps2;
    if (options.add_noise) {
      sample.gyro_rad_s += gyro_noise_rad_s * n_g;
      sample.accel_mps2 += accel_noise_mps2 * n_a;
    }
    if (saturate(sample.gyro_rad_s, noise.gyro_saturation_rad_s)) ++result.gyro_clipped_samples;
    if (saturate(sample.accel_mps2, noise.accel_saturation_mps2)) ++result.accel_clipped_samples;
    result.samples.push_back(sample);

    GroundTruthState state;
    state.t_ns = t_ns;
    state.p_W_S = kin.T_W_S.translation();
    state.q_W_S = kin.T_W_S.quaternion();
    state.v_W_S = kin.v_W_mps;
    state.b_g = b_g_rad_s;
    state.b_a = b_a_total_mps2;
    result.states.push_back(state);

    if (options.add_biases) {
      b_g_rad_s += gyro_walk_rad_s * w_g;
      b_a_mps2 += accel_walk_mps2 * w_a;
    }
  }
  return result;
}

}  // namespace vifusion::sim
