#pragma once
// Device tick counts to nanoseconds, exactly. The ZR300 motion module counts at 32 MHz, 31.25 ns per
// tick: multiplying by a rounded 31 or 31.3 ns would drift by 0.25 ns per tick (8 ms per second), and a
// double of milliseconds (librealsense v1) loses nanoseconds once the count is large. Here the whole
// seconds and the remainder are converted separately in int64 arithmetic, so the result is the exact
// value rounded to the nearest nanosecond (halves up) and never overflows for counts that fit an int64.

#include <cstdint>

#include "vifusion/core/time.hpp"

namespace vifusion::clock {

/// Tick rate of the ZR300 motion module's microcontroller clock [ticks/s] (sensors.md §1.4: 1 tick =
/// 31.25 ns). IMU samples and camera-frame events carry its low 32 bits.
inline constexpr std::int64_t kZr300MotionTicksPerSecond = 32'000'000;

/// Nanoseconds from `ticks` counted at `ticks_per_second`, rounded to nearest (halves up). Exact for any
/// ticks >= 0 and 0 < ticks_per_second <= 9'000'000'000 (the remainder times 1e9 stays below 2^63).
/// Monotone non-decreasing in `ticks`, so a monotone unwrapped count gives monotone times.
constexpr std::int64_t ticksToNs(std::int64_t ticks, std::int64_t ticks_per_second) {
  const std::int64_t whole_s = ticks / ticks_per_second;
  const std::int64_t remainder_ticks = ticks % ticks_per_second;
  return whole_s * kNsPerSecond + (remainder_ticks * kNsPerSecond + ticks_per_second / 2) / ticks_per_second;
}

/// The tick count nearest to `t_ns` (halves up), the inverse of ticksToNs for simulations and tests.
/// Same range: t_ns >= 0, 0 < ticks_per_second <= 9'000'000'000.
constexpr std::int64_t nsToTicks(std::int64_t t_ns, std::int64_t ticks_per_second) {
  const std::int64_t whole_s = t_ns / kNsPerSecond;
  const std::int64_t remainder_ns = t_ns % kNsPerSecond;
  return whole_s * ticks_per_second + (remainder_ns * ticks_per_second + kNsPerSecond / 2) / kNsPerSecond;
}

/// ZR300 motion-module ticks (already unwrapped, >= 0) to nanoseconds of device time.
constexpr std::int64_t zr300TicksToNs(std::int64_t ticks) { return ticksToNs(ticks, kZr300MotionTicksPerSecond); }

}  // namespace vifusion::clock
