#pragma once
// Options of ClockMapper (clock_mapper.hpp): how much history the lower hull keeps, when its fit counts
// as valid, and what the mapper treats as a clock step rather than latency. Defaults suit the ZR300
// motion module: ~450 interrupt transfers/s, USB latency of a few hundred µs with ms-scale outliers, a
// crystal within ±100 ppm whose rate wanders by a few ppm with temperature.

#include <cstddef>
#include <cstdint>

namespace vifusion::clock {

struct ClockMapperOptions {
  /// Largest step_confirm_samples: the mapper keeps that many held-back samples in a fixed array.
  static constexpr std::size_t kMaxStepConfirmSamples = 64;

  /// Length of the sliding window in device time [s]. Older samples expire, so a drift change (the
  /// crystal warming up) is followed fully one window after it happened; a longer window averages the
  /// skew over more samples. Drift changes of a few ppm per minute make 20 s a fair trade. (0, 3600].
  double window_s = 20.0;
  /// Most samples the window holds: the memory reserved at construction (32 B per sample: the point, a
  /// hull slot and a scratch slot). When full the oldest expire even if younger than window_s. 16384
  /// covers 20 s at 450 transfers/s with room for faster links. >= min_samples.
  std::size_t window_samples = 16384;
  /// Device-time span the window must cover before the hull's fit is used [s]. Before that the mapper
  /// only shifts by the lowest-latency sample (with the last valid skew, or 0) and says kWarmingUp. 2 s is
  /// where the fit already beats that (µs against a sample's latency of up to hundreds of µs), not where
  /// it is best: the skew keeps sharpening until the window is full. (0, window_s).
  double min_span_s = 2.0;
  /// Samples the window must hold before the fit is used. >= 2.
  std::size_t min_samples = 64;
  /// The fixed part of the transfer latency [ns] (USB polling interval, firmware packing), subtracted
  /// from every host time. One-way timing cannot see it: a constant delay looks exactly like an offset,
  /// so the lower bound the mapper finds is "true time + the smallest latency". Leave 0 when the
  /// camera–IMU time shift is calibrated (Kalibr's timeshift_cam_imu absorbs it). [0, 1e9).
  std::int64_t fixed_latency_ns = 0;
  /// How far a sample may arrive EARLIER than the valid mapping predicts [ns]. Latency only delays, so
  /// an early arrival beyond the fit's own error means the clocks stepped (host suspend: CLOCK_MONOTONIC
  /// stops while the device counts on) or the device time is corrupt. Such samples are held back and
  /// counted; see step_confirm_samples. The fit's error is µs, and a drift change of Δ ppm puts new
  /// samples below it by at most Δ·window_s/2 (10 ppm → 100 µs), so 1 ms rejects no real sample. Not
  /// applied while kWarmingUp: that mapping rests on one sample whose own latency is unknown (it may be
  /// a 20 ms outlier), so "early" means nothing yet. > 0.
  std::int64_t max_early_ns = 1'000'000;
  /// Consecutive, mutually consistent samples that must disagree with the window (earlier than
  /// max_early_ns, or device time not after the window's newest) before the mapper believes a clock step
  /// and restarts from them. One corrupt timestamp is dropped; a real step costs this many samples
  /// (8 at 450 transfers/s: 18 ms). [1, kMaxStepConfirmSamples].
  std::size_t step_confirm_samples = 8;
  /// window_s in device nanoseconds.
  std::int64_t windowNs() const;
  /// min_span_s in device nanoseconds.
  std::int64_t minSpanNs() const;

  /// @throws vifusion::Error naming the first bad field and its allowed range.
  void validate() const;
};

}  // namespace vifusion::clock
