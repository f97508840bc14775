#pragma once
// Shared pieces of the IMU tests: smooth synthetic sample streams with known closed forms, random
// non-trivial states and extrinsics, and small helpers. Fixed seeds, so a failure replays exactly.

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "vifusion/test/random_inputs.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/core/sensor_data.hpp"
#include "vifusion/core/so3.hpp"
#include "vifusion/core/state.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/imu/preintegration.hpp"

namespace vifusion::imu::test {

using vifusion::test::RandomInputs;

inline constexpr std::int64_t kPeriodNs = 5'000'000;  ///< 200 Hz, Table I

/// Per-axis a + b·sin(2π·f·t + φ): smooth readings with rates and forces of a hand-held camera.
struct SineSignal {
  Eigen::Vector3d offset, amplitude, frequency_hz, phase_rad;

  static SineSignal random(RandomInputs& rnd, double offset, double amplitude) {
    SineSignal s;
    s.offset = rnd.vector<3>(offset);
    s.amplitude = rnd.vector<3>(amplitude);
    s.frequency_hz = Eigen::Vector3d(rnd.uniform(0.5, 2.0), rnd.uniform(0.5, 2.0), rnd.uniform(0.5, 2.0));
    s.phase_rad = rnd.vector<3>(std::numbers::pi);
    return s;
  }

  Eigen::Vector3d operator()(std::int64_t t_ns) const {
    const double t_s = nsToSeconds(t_ns);
    Eigen::Vector3d v;
    for (int i = 0; i < 3; ++i) {
      v[i] = offset[i] + amplitude[i] * std::sin(2.0 * std::numbers::pi * frequency_hz[i] * t_s + phase_rad[i]);
    }
    return v;
  }
};

/// `count` samples every kPeriodNs from t_begin_ns: |ω| up to ~2.5 rad/s, |a| ~ 10 ± 4 m/s² (gravity-like).
inline std::vector<ImuSample> smoothSamples(unsigned seed, std::int64_t t_begin_ns, int count) {
  RandomInputs rnd(seed);
  const SineSignal gyro = SineSignal::random(rnd, 0.8, 1.0);
  SineSignal accel = SineSignal::random(rnd, 2.0, 3.0);
  accel.offset.z() += 9.81;
  std::vector<ImuSample> samples(static_cast<std::size_t>(count));
  for (int k = 0; k < count; ++k) {
    ImuSample& s = samples[static_cast<std::size_t>(k)];
    s.t_ns = t_begin_ns + k * kPeriodNs;
    s.gyro_rad_s = gyro(s.t_ns);
    s.accel_mps2 = accel(s.t_ns);
  }
  return samples;
}

/// A state far from the identity: metres away, any orientation, moving, biased, gravity rotated.
inline NavState randomState(RandomInputs& rnd) {
  NavState x;
  x.r_W_C = rnd.vector<3>(5.0);
  x.q_W_C = rnd.rotation();
  x.v_I_S = rnd.vector<3>(2.0);
  x.b_g = rnd.vector<3>(0.03);
  x.b_a = rnd.vector<3>(0.2);
  x.q_I_W = rnd.rotation();
  return x;
}

/// A camera → IMU transform with a lever arm of centimetres and a visible misalignment.
inline SE3d randomT_S_C(RandomInputs& rnd) { return SE3d(expSO3(rnd.rotationVector(0.6)), rnd.vector<3>(0.08)); }

/// Right-perturbation difference of two rotations, log(q_aᵀ·q_b) [rad].
inline Eigen::Vector3d rotationDifference(const Eigen::Quaterniond& q_a, const Eigen::Quaterniond& q_b) {
  return logSO3(q_a.conjugate() * q_b);
}

/// Integrates and fails the test on any sample issue.
inline PreintegratedImu integrateOrFail(const ImuPreintegrator& integrator, const std::vector<ImuSample>& samples,
                                        std::int64_t t0_ns, std::int64_t t1_ns, const Eigen::Vector3d& b_g,
                                        const Eigen::Vector3d& b_a) {
  PreintegratedImu pre;
  const auto issue = integrator.integrate(samples, t0_ns, t1_ns, b_g, b_a, pre);
  EXPECT_FALSE(issue.has_value()) << issue->message();
  return pre;
}

}  // namespace vifusion::imu::test
