#include "vifusion/imu/imu_options.hpp"

#include <cmath>
#include <string>

#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion::imu {
namespace {

void require(bool ok, double value, const char* name, const char* condition) {
  if (!ok || !std::isfinite(value)) {
    throw Error(std::string("IMU option '") + name + "' = " + std::to_string(value) + " must be finite and " +
                condition);
  }
}

}  // namespace

std::int64_t ImuOptions::maxGapNs() const {
  return std::llround(max_gap_periods * static_cast<double>(kNsPerSecond) / noise.rate_hz);
}

void ImuOptions::validate() const {
  noise.validate();
  require(noise.gyro_noise_density > 0.0, noise.gyro_noise_density, "noise.gyro_noise_density", "> 0");
  require(noise.accel_noise_density > 0.0, noise.accel_noise_density, "noise.accel_noise_density", "> 0");
  require(noise.gyro_random_walk > 0.0, noise.gyro_random_walk, "noise.gyro_random_walk", "> 0");
  require(noise.accel_random_walk > 0.0, noise.accel_random_walk, "noise.accel_random_walk", "> 0");
  require(max_gap_periods > 1.0, max_gap_periods, "max_gap_periods", "> 1");
  require(saturation_noise_factor >= 1.0, saturation_noise_factor, "saturation_noise_factor", ">= 1");
  require(reintegrate_above_rad > 0.0, reintegrate_above_rad, "reintegrate_above_rad", "> 0");
  require(gravity_direction_random_walk > 0.0, gravity_direction_random_walk, "gravity_direction_random_walk", "> 0");
}

}  // namespace vifusion::imu
