#include "vifusion/core/imu_noise.hpp"

#include <cmath>

#include "vifusion/core/error.hpp"

namespace vifusion {

ImuNoiseParams ImuNoiseParams::synthetic() { return ImuNoiseParams{}; }

ImuNoiseParams ImuNoiseParams::zr300() {
  ImuNoiseParams params;
  params.accel_noise_density = 8.0e-2;
  params.accel_bias_prior = 1.0;
  params.static_accel_bias_mps2 = Eigen::Vector3d(0.060, 0.258, 0.126);
  return params;
}

ImuNoiseParams ImuNoiseParams::preset(const std::string& name) {
  if (name == "synthetic") return synthetic();
  if (name == "zr300") return zr300();
  throw Error("unknown IMU noise preset '" + name + "' (expected 'synthetic' or 'zr300')");
}

void ImuNoiseParams::validate() const {
  const auto require = [](double value, bool positive, const char* name) {
    if (!std::isfinite(value) || value < 0.0 || (positive && value == 0.0)) {
      throw Error(std::string("IMU parameter '") + name + "' = " + std::to_string(value) +
                  (positive ? " must be finite and > 0" : " must be finite and ≥ 0"));
    }
  };
  require(gyro_saturation_rad_s, true, "gyro_saturation_rad_s");
  require(accel_saturation_mps2, true, "accel_saturation_mps2");
  require(gyro_noise_density, false, "gyro_noise_density");
  require(accel_noise_density, false, "accel_noise_density");
  require(gyro_bias_prior, false, "gyro_bias_prior");
  require(accel_bias_prior, false, "accel_bias_prior");
  require(gyro_random_walk, false, "gyro_random_walk");
  require(accel_random_walk, false, "accel_random_walk");
  require(gravity_mps2, true, "gravity_mps2");
  require(rate_hz, true, "rate_hz");
  if (!static_accel_bias_mps2.allFinite()) throw Error("IMU parameter 'static_accel_bias_mps2' is not finite");
}

}  // namespace vifusion
