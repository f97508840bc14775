#pragma once
// Settings of the timestamp-sync analysis (analyse.hpp): what the rig should do and the pass/fail limits,
// each defined once, with the range validate() enforces. The defaults come from the ZR300's documented
// timing (shared/reference/sensors.md §1): a 30 Hz depth/colour stream, a 200 Hz-class IMU (gyro 200 Hz,
// accel 250 Hz, interleaved), motion-module packets of at most 4 IMU entries, a 32 MHz device clock that
// the ClockMapper (clock_mapper.hpp) re-fits over a 20 s window.

#include <cstdint>
#include <optional>
#include <string_view>

#include "vifusion/synccheck/zr300_timing.hpp"

namespace vifusion::synccheck {

/// Which sync-line edge marks a frame: the strobe's leading edge (start of exposure) is the rising one.
enum class EdgePolarity : std::uint8_t { kRising, kFalling };

/// "rising" or "falling".
std::string_view edgePolarityName(EdgePolarity polarity);
/// The inverse of edgePolarityName(); nullopt for anything else (the caller names its option).
std::optional<EdgePolarity> parseEdgePolarity(std::string_view text);

struct SyncCheckOptions {
  /// The camera's frame rate [Hz], (0, kMaxRateHz]: the pairing's frame period when fewer than two edges
  /// exist, and the reference of the frame-rate check.
  double expected_frame_rate_hz = kZr300FrameRateHz;
  /// The IMU's sample rate [Hz], (0, kMaxRateHz]: the reference of the IMU-rate check.
  double expected_imu_rate_hz = kZr300ImuRateHz;
  /// The edge of each strobe pulse that a frame is paired with; the other polarity is ignored.
  EdgePolarity edge_polarity = EdgePolarity::kRising;
  /// Width of CameraFrameTimes::device_frame_number [bits], [kMinFrameNumberBits, 32]: 32 for the DS4
  /// metadata counter, 12 for the motion module's event numbers. Differences are taken modulo 2^bits.
  int frame_number_bits = 32;
  /// Half-width of the window a frame's edge must fall in, as a fraction of the frame period, (0, 0.5):
  /// around the predicted offset, so a neighbouring edge (one period away) never pairs. 0.25 (8.3 ms at
  /// 30 Hz) leaves stamps 50 jitter std (of 150 µs) of room while rejecting the wrong edge by 8 ms.
  double pairing_window_fraction = 0.25;
  /// true: no IMU sample at all fails the IMU checks; false: they are skipped then (a camera-only rig).
  bool require_imu = true;

  // Pass/fail limits. Each check is named in SyncReport::checks.
  /// "offset": |median(frame stamp − edge)| [ns], >= 0. One IMU period (5 ms at 200 Hz): a constant offset
  /// below it moves frames by less than one IMU sample interval, which the camera–IMU time shift
  /// calibration absorbs; beyond it a stamp is more likely wrong (kernel fallback, a mis-paired event).
  std::int64_t max_abs_offset_ns = kZr300ImuPeriodNs;
  /// "jitter": p99 of |residual| about the robust line fit [ns], >= 0. A fifth of an IMU period (1 ms):
  /// preintegration between frames then starts and ends within a fifth of a sample of the right place.
  std::int64_t max_jitter_p99_ns = kZr300ImuPeriodNs / 5;
  /// "drift": |slope| of (frame stamp − edge) over time [ppm], >= 0. The ClockMapper re-fits the device
  /// clock's skew over a 20 s window; a drift that walks more than the jitter limit (1 ms) across one
  /// window (1 ms / 20 s = 50 ppm) is the mapping not following, not noise.
  double max_abs_drift_ppm = 50.0;
  /// "dropped": dropped / expected frames, [0, 1]. A judgement, not a datasheet number: rgbdi mode bridges
  /// a missing frame with the IMU, and one frame in 50 (one every 1.7 s at 30 Hz) still leaves tracking
  /// mostly frame-to-frame; more points at a stalled consumer or a saturated USB link.
  double max_dropped_fraction = 0.02;
  /// "imu_gap": the largest interval between consecutive IMU samples [ns], > 0. Four IMU periods (20 ms):
  /// a lost motion-module packet (<= 4 entries, gyro and accel interleaved) removes about two gyro
  /// samples, an interval of three periods; two lost packets in a row exceed four.
  std::int64_t max_imu_gap_ns = 4 * kZr300ImuPeriodNs;
  /// "frame_rate" and "imu_rate": |measured / expected − 1|, (0, 1). The rates the devices offer differ
  /// by >= 25 % (30/60/90 fps; 200 Hz gyro vs 250 Hz accel) and crystals by < 0.01 %, so 5 % catches a
  /// wrong mode and nothing else.
  double max_rate_error_fraction = 0.05;

  static constexpr double kMaxRateHz = 10'000.0;  ///< above any camera or IMU rate: a unit mistake
  static constexpr int kMinFrameNumberBits = 4;   ///< a counter wrapping within 16 frames tells nothing

  /// The nominal frame period [ns] (from expected_frame_rate_hz).
  std::int64_t framePeriodNs() const;
  /// @throws vifusion::Error naming the first bad field, its value and the allowed range.
  void validate() const;
};

}  // namespace vifusion::synccheck
