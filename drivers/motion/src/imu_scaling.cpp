#include "vifusion/motion/imu_scaling.hpp"

#include <algorithm>
#include <numbers>
#include <sstream>

#include "vifusion/core/error.hpp"

namespace vifusion::motion {
namespace {

template <std::size_t N>
void requireChoice(double value, const std::array<double, N>& choices, const char* field) {
  if (std::find(choices.begin(), choices.end(), value) != choices.end()) return;
  std::ostringstream message;
  message << "imu range option '" << field << "' = " << value << " is not a range the motion module offers (";
  for (std::size_t i = 0; i < N; ++i) message << (i == 0 ? "" : " or ") << choices[i];
  message << ")";
  throw Error(message.str());
}

}  // namespace

void ImuRangeOptions::validate() const {
  requireChoice(gyro_full_scale_deg_s, kGyroFullScaleChoicesDegS, "gyro_full_scale_deg_s");
  requireChoice(accel_full_scale_g, kAccelFullScaleChoicesG, "accel_full_scale_g");
}

ImuScaler::ImuScaler(const ImuRangeOptions& options)
    : gyro_rad_s_per_count_(
          (options.validate(), options.gyro_full_scale_deg_s * std::numbers::pi / 180.0 / kGyroCountsAtFullScale)),
      accel_mps2_per_count_(kStandardGravityMps2 * options.accel_full_scale_g / kAccelCountsAtFullScale) {}

Eigen::Vector3d ImuScaler::gyroRadS(const std::array<std::int16_t, kAxisCount>& raw_xyz) const {
  return Eigen::Vector3d(raw_xyz[0], raw_xyz[1], raw_xyz[2]) * gyro_rad_s_per_count_;
}

Eigen::Vector3d ImuScaler::accelMps2(const std::array<std::int16_t, kAxisCount>& raw_xyz) const {
  // C++20 defines >> on negative values as arithmetic: −16 >> 4 = −1.
  const auto counts = [&](std::size_t axis) { return static_cast<double>(raw_xyz[axis] >> kAccelDataShiftBits); };
  return Eigen::Vector3d(counts(0), counts(1), counts(2)) * accel_mps2_per_count_;
}

}  // namespace vifusion::motion
