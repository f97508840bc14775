#pragma once
// Raw motion-module axis words → SI units (sensors.md §1.4):
//   gyro  [rad/s]  = count · (full scale [°/s] · π/180) / 32767
//   accel [m/s²]   = (word >> 4) · g · full scale [g] / 2048     (the reading is in the word's 12 MSBs; the
//                                                                shift is arithmetic, so the sign is kept)
// The full-scale ranges are the only settings: the firmware defaults (±1000 °/s, ±4 g) apply because
// librealsense v1.12.4 cannot configure the module; a unit configured to 2000 °/s or 8/16 g is one option
// away. Per-device intrinsics (scale, misalignment, bias from the adapter EEPROM) are calibration and are
// not applied here.

#include <Eigen/Core>
#include <array>
#include <cstdint>

#include "vifusion/motion/packet_format.hpp"

namespace vifusion::motion {

inline constexpr double kStandardGravityMps2 = 9.80665;    ///< the g of the accelerometer's range, by definition
inline constexpr double kGyroCountsAtFullScale = 32767.0;  ///< 16-bit signed reading at +full scale
inline constexpr double kAccelCountsAtFullScale = 2048.0;  ///< 12-bit signed reading at full scale
inline constexpr unsigned kAccelDataShiftBits = 4;         ///< 16-bit word → its 12 significant bits

/// Ranges offered by the motion module (register 0x68 gyro range, 0x64 accel range).
inline constexpr std::array<double, 2> kGyroFullScaleChoicesDegS{1000.0, 2000.0};
inline constexpr std::array<double, 3> kAccelFullScaleChoicesG{4.0, 8.0, 16.0};

struct ImuRangeOptions {
  double gyro_full_scale_deg_s = 1000.0;  ///< ± range the gyro is configured to [°/s]: 1000 or 2000
  double accel_full_scale_g = 4.0;        ///< ± range the accelerometer is configured to [g]: 4, 8 or 16
  /// @throws vifusion::Error naming the field if a range is not one the module offers.
  void validate() const;
};

/// Converts raw axis words; a pure function of the ranges, safe to share between threads.
class ImuScaler {
 public:
  /// @throws vifusion::Error if options.validate() does.
  explicit ImuScaler(const ImuRangeOptions& options = {});

  /// Angular rate of the IMU frame S [rad/s] from the gyro's raw words.
  Eigen::Vector3d gyroRadS(const std::array<std::int16_t, kAxisCount>& raw_xyz) const;
  /// Specific force in S [m/s²] from the accelerometer's raw words (12 MSBs used).
  Eigen::Vector3d accelMps2(const std::array<std::int16_t, kAxisCount>& raw_xyz) const;

  double gyroRadSPerCount() const { return gyro_rad_s_per_count_; }
  double accelMps2PerCount() const { return accel_mps2_per_count_; }  ///< per 12-bit count (after the shift)

 private:
  double gyro_rad_s_per_count_ = 0.0;
  double accel_mps2_per_count_ = 0.0;
};

}  // namespace vifusion::motion
