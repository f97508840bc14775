#pragma once
// A simulated ZR300 + sync line with known timing errors, so that the analysis' own accuracy is testable
// (`vifusion synccheck --simulate`). Defaults: issue 18's acceptance case (offset 3.2 ms, drift 40 ppm,
// jitter 150 µs, 1 % dropped frames, 60 s at 30 Hz).
//
// WHAT HAPPENS PER FRAME k (host CLOCK_MONOTONIC, s_k = start_ns + k·period, the strobe's leading edge):
// - Sync line: a rising edge at s_k and a falling one at s_k + strobe_width_ns, each stamped by the GPIO
//   interrupt after a latency of edge_latency_ns + Exp(mean edge_latency_spread_ns) (one-sided).
// - Frame event: the motion module stamps the frame at host time s_k + offset_ns + N(0, jitter_ns) on its
//   own clock, device = device_origin_ns + (host − start_ns)·(1 + device_skew_ppm·1e-6), in 32 MHz ticks
//   (31.25 ns, truncated). The host maps it back with a mapping whose rate is off by drift_ppm (the
//   clock mapper's skew error), so the mapped stamp walks away from the strobe by drift_ppm·1e-6 per
//   second. offset_ns lumps the event's place in the exposure and the mapping's offset error.
// - Kernel stamp: s_k + kernel_offset_ns + N(0, kernel_jitter_ns) (uvcvideo's buffer time, mid-exposure).
// - The frame's stamp t_ns is the mapped event, or the kernel's when the event did not arrive
//   (probability 1 − event_probability), as Zr300Source does.
// - Delivery: lost with drop_probability (its strobe, event and device number still happen), else
//   delivered, and then delivered twice with duplicate_probability. The first and the last strobe's frames
//   are always delivered, so every drop lies between two delivered frames, where a drop can be seen.
// IMU samples: every 1/imu_rate_hz of device time, mapped like the frame events (drift included), plus
// N(0, imu_jitter_ns). Clock-mapper residuals: one per motion-module packet (kZr300ImuEntriesPerPacket
// samples), Exp(mean mapper_latency_mean_ns): the transfer's latency above the mapped line.
//
// EXPECTED ANALYSIS (what a test compares with): frame_minus_edge starts at offset_ns − mean edge latency
// and drifts by drift_ppm; its jitter std is sqrt(jitter² + spread²) (an exponential's std is its mean).

#include <cstddef>
#include <cstdint>

#include "vifusion/core/time.hpp"
#include "vifusion/synccheck/sync_input.hpp"
#include "vifusion/synccheck/zr300_timing.hpp"

namespace vifusion::synccheck {

struct ClockModel {
  double frame_rate_hz = kZr300FrameRateHz;     ///< strobe rate [Hz], (0, 1000]
  double duration_s = 60.0;                     ///< simulated time [s], (0, 86400]; strobes: floor(duration·rate)
  std::int64_t start_ns = 100 * kNsPerSecond;   ///< host time of the first strobe [ns], > 0 (a booted host)
  std::int64_t offset_ns = 3'200'000;           ///< frame stamp − strobe at the first frame [ns], |.| < period / 2
  double drift_ppm = 40.0;                      ///< growth rate of that offset [ppm], |.| <= kMaxModelPpm
  std::int64_t jitter_ns = 150'000;             ///< Gaussian std of the frame event [ns], >= 0
  std::int64_t edge_latency_ns = 15'000;        ///< fixed part of the GPIO interrupt latency [ns], >= 0
  std::int64_t edge_latency_spread_ns = 5'000;  ///< mean of its exponential part [ns], >= 0
  std::int64_t strobe_width_ns = 1'000'000;     ///< rising to falling edge [ns], (0, period)
  double drop_probability = 0.01;               ///< frame lost on the host side, [0, 0.5]
  double duplicate_probability = 0.0;           ///< delivered frame delivered again, [0, 0.5]
  double event_probability = 1.0;               ///< frame event arrives in time, [0, 1]
  std::int64_t kernel_offset_ns = 4'000'000;    ///< kernel stamp − strobe [ns], |.| < period / 2
  std::int64_t kernel_jitter_ns = 250'000;      ///< its Gaussian std [ns], >= 0
  std::int64_t device_origin_ns = 7 * kNsPerSecond;  ///< device clock at the first strobe [ns], >= 0
  double device_skew_ppm = 25.0;                     ///< device clock rate − host rate [ppm], |.| <= kMaxModelPpm
  std::uint32_t first_frame_number = 1000;           ///< device frame counter of the first strobe
  double imu_rate_hz = kZr300ImuRateHz;              ///< IMU rate in device time [Hz], (0, 10000]
  std::int64_t imu_jitter_ns = 20'000;               ///< Gaussian std of an IMU stamp [ns], >= 0
  std::int64_t mapper_latency_mean_ns = 300'000;     ///< mean transfer latency above the mapping [ns], >= 0

  static constexpr double kMaxModelPpm = 1000.0;  ///< beyond any crystal: a unit mistake
  static constexpr double kMaxDurationS = 86'400.0;
  static constexpr double kMaxFrameRateHz = 1'000.0;
  static constexpr double kMaxImuRateHz = 10'000.0;
  static constexpr double kMaxLossProbability = 0.5;  ///< more and "the frame's neighbours" mean nothing

  std::int64_t framePeriodNs() const;
  /// frame_minus_edge at the first frame as the analysis should report it [ns].
  double expectedOffsetNs() const;
  /// frame_minus_edge's jitter std as the analysis should report it [ns].
  double expectedJitterStdNs() const;
  /// @throws vifusion::Error naming the first bad field, its value and the allowed range.
  void validate() const;
};

/// What the simulator did, for tests to compare the analysis with.
struct SimulationTruth {
  std::size_t strobes = 0;
  std::size_t dropped_frames = 0;
  std::size_t duplicated_frames = 0;
  std::size_t kernel_stamped_frames = 0;  ///< delivered frames (duplicates included) without an event
};

/// Simulates `model` with the random stream `seed` (the same seed gives the same input on one standard
/// library). @throws vifusion::Error when the model is invalid.
SyncInput simulate(const ClockModel& model, std::uint64_t seed, SimulationTruth* truth = nullptr);

}  // namespace vifusion::synccheck
