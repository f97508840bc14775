#pragma once
// The ZR300's documented timing (shared/reference/sensors.md §1), which the option defaults
// (sync_check_options.hpp) are derived from and the simulator (clock_model.hpp) reproduces.

#include <cstdint>

#include "vifusion/core/time.hpp"

namespace vifusion::synccheck {

/// Depth and colour at 30 fps (the rate vifusion streams; the DS4 also offers 60 and 90).
inline constexpr double kZr300FrameRateHz = 30.0;
/// The IMU's nominal rate: gyro 200 Hz (accel 250 Hz, interleaved in the same packets).
inline constexpr double kZr300ImuRateHz = 200.0;
inline constexpr std::int64_t kZr300ImuPeriodNs = static_cast<std::int64_t>(kNsPerSecond / kZr300ImuRateHz);
/// IMU entries one 104-byte motion-module packet carries at most (§1.4).
inline constexpr int kZr300ImuEntriesPerPacket = 4;
/// One tick of the motion module's 32 MHz clock [ns] (§1.4).
inline constexpr double kZr300DeviceTickNs = 31.25;

}  // namespace vifusion::synccheck
