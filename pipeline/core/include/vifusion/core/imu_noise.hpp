#pragma once
// IMU noise model of Nikolic et al. (Sensors 2016) / Kalibr, with the values of the paper's
// Table I. Densities are continuous-time; a sample at rate f has white-noise σ_d = σ·√f and a
// bias that random-walks by σ_b/√f per sample. Shared by the simulator and the estimator.

#include <Eigen/Core>
#include <string>

namespace vifusion {

struct ImuNoiseParams {
  double gyro_saturation_rad_s = 7.8;       ///< |ω| per axis beyond which readings clip [rad/s]
  double accel_saturation_mps2 = 176.0;     ///< |a| per axis beyond which readings clip [m/s²]
  double gyro_noise_density = 12.0e-4;      ///< σ_g [rad/s/√Hz]
  double accel_noise_density = 8.0e-3;      ///< σ_a [m/s²/√Hz]
  double gyro_bias_prior = 0.03;            ///< 1σ of the initial gyro bias [rad/s]
  double accel_bias_prior = 0.1;            ///< 1σ of the initial accelerometer bias [m/s²]
  double gyro_random_walk = 4.0e-6;         ///< σ_bg, gyro bias drift [rad/s²/√Hz]
  double accel_random_walk = 2.0e-5;        ///< σ_ba, accelerometer bias drift [m/s³/√Hz]
  double gravity_mps2 = 9.81;               ///< magnitude of gravity [m/s²]
  double rate_hz = 200.0;                   ///< sample rate [Hz]
  /// Constant accelerometer bias on top of the random one [m/s²] (the real ZR300 showed one).
  Eigen::Vector3d static_accel_bias_mps2 = Eigen::Vector3d::Zero();

  /// Table I, synthetic column (the default).
  static ImuNoiseParams synthetic();
  /// Table I, real-world (ZR300) column: 10× accelerometer noise, 1 m/s² bias prior, static bias.
  static ImuNoiseParams zr300();
  /// "synthetic" or "zr300"; throws vifusion::Error naming the unknown preset.
  static ImuNoiseParams preset(const std::string& name);

  /// Throws vifusion::Error naming the first field that is negative, non-finite or (rate, gravity,
  /// saturations) not positive.
  void validate() const;
};

}  // namespace vifusion
