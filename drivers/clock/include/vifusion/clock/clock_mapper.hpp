#pragma once
// Maps a device clock (the ZR300 motion module's unwrapped 32 MHz ticks, in ns) onto host
// CLOCK_MONOTONIC ns, online, following drift, robust to USB latency outliers (DESIGN.md §3, time).
//
// MODEL. A transfer stamped at device time x arrives at host time
//     y = offset + (1 + skew)·x + latency,   latency >= 0,
// with latency = USB polling + scheduling + bus contention: a few hundred µs, sometimes milliseconds.
// The wanted mapping is the line offset + (1 + skew)·x, a LOWER BOUND of every (x, y).
//
// WHY A LOWER HULL, NOT LEAST SQUARES. Least squares assumes zero-mean, symmetric, light-tailed noise.
// Latency is one-sided and heavy-tailed: a regression line sits at the MEAN latency (hundreds of µs above
// the truth, and that bias moves whenever the bus load changes), and every millisecond outlier tilts it.
// Only the smallest delays carry information, and they are found exactly: the lower convex hull of the
// points. Outliers sit above the hull and change nothing; the hull's error is set by how close the
// fastest transfers come to zero extra latency, which shrinks like μ/N for exponential latency of mean μ
// and N samples, not like μ/√N. TICSync (Harrison, Newman, ICRA 2011) and Moon, Skelly, Towsley
// ("Estimation and removal of clock skew from network delay measurements", INFOCOM 1999) rest on the
// same one-sided-delay hull; librealsense's "global time" instead fits a line to the recent samples with
// the smallest command round trip. A constant part of the latency cannot be told from an offset by
// one-way timing (ClockMapperOptions::fixed_latency_ns).
//
// THE FIT. Skew: the slope of the chord of the hull between the points a quarter of the window's span
// in from each end. Offset: the hull vertex where a line of that slope touches the hull, so the line lies
// under every sample, as the lower bound must. Moon's linear program takes instead the single hull edge
// over the window's mean time; that edge's two vertices can be close together, and a slope from two
// nearby samples is noisy where a chord over half the window is not. The chord stays clear of the ends
// because the hull's end edges run up to the newest and oldest samples, whatever their latency.
//
// DRIFT. Only the last window_s of samples (at most window_samples) is kept (SlidingLowerHull); old
// vertices expire, so a skew change is followed completely one window after it happened, and partly at
// once (the hull's newest vertices follow it).
//
// CONDITIONING. The estimate is kept as a reference point on the hull (a real sample, integer ns) plus
// the skew: host = ref_host + (x − ref_device)·(1 + skew). Only differences across one window meet a
// double, so nanoseconds are exact at any uptime.
//
// STATES. kEmpty: nothing to map with. kWarmingUp: fewer than min_samples or less than min_span_s of
// device time; the mapping is the lowest-latency sample with the last valid skew (0 before the first
// fit), good to that sample's latency but not to µs. kValid: the hull fit.
//
// STEPS. A sample arriving more than max_early_ns before the valid mapping (latency cannot be negative), or
// whose device time does not advance, is held back and counted. step_confirm_samples such samples in a
// row that agree with each other mean the clocks really stepped (host suspend, device counter restart):
// the window restarts from them. A single corrupt timestamp is dropped without disturbing the fit; a
// repeated transfer neither confirms nor breaks a run.
// Not detected: a device clock that steps BACK relative to the host (samples then look late, like
// latency); the fit follows once the old vertices expire, one window later.
//
// Memory: everything is sized at construction; addSample() and toHostNs() never allocate. Threads: one
// producer calls addSample(); reads from another thread need the caller's synchronisation.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

#include "vifusion/clock/clock_mapper_options.hpp"
#include "vifusion/clock/clock_sample_result.hpp"
#include "vifusion/clock/sliding_lower_hull.hpp"

namespace vifusion::clock {

enum class ClockMapperState {
  kEmpty,      ///< no sample yet, or none since reset(): toHostNs() gives nullopt
  kWarmingUp,  ///< shift by the lowest-latency sample only; not yet µs-accurate
  kValid,      ///< hull fit over >= min_span_s and >= min_samples
};

const char* clockMapperStateName(ClockMapperState state);

/// A device→host mapping: host = ref_host_ns + (device − ref_device_ns)·(1 + skew).
struct ClockEstimate {
  std::int64_t ref_device_ns = 0;  ///< reference point: a hull vertex's device time [ns]
  std::int64_t ref_host_ns = 0;    ///< its host time on the fitted line, fixed_latency_ns removed [ns]
  double skew = 0.0;  ///< host rate / device rate − 1 [dimensionless]; +50e-6: the host gains 50 µs per device s

  /// The host time of `device_ns` [ns]. Precondition: device_ns in [0, kMaxClockTimeNs].
  std::int64_t toHostNs(std::int64_t device_ns) const;
  /// host − device at the reference point [ns].
  std::int64_t offsetNs() const { return ref_host_ns - ref_device_ns; }
  double skewPpm() const;  ///< skew in parts per million
};

/// Counts of what addSample() did since construction (reset() keeps them).
struct ClockMapperStats {
  std::uint64_t samples = 0;                ///< addSample() calls
  std::uint64_t accepted = 0;               ///< kAccepted + kRestarted
  std::uint64_t out_of_range = 0;           ///< kOutOfRange
  std::uint64_t device_not_increasing = 0;  ///< kDeviceNotIncreasing
  std::uint64_t host_backwards = 0;         ///< kHostBackwards
  std::uint64_t early = 0;                  ///< kEarly
  std::uint64_t restarts = 0;               ///< kRestarted: confirmed clock steps
  std::uint64_t held_back_used = 0;         ///< held-back samples that a restart put into the window

  /// Samples that did not enter the window (some held back, then used by a restart, count here too).
  std::uint64_t rejected() const { return out_of_range + device_not_increasing + host_backwards + early; }
};

class ClockMapper {
 public:
  /// Validates `options` (throws vifusion::Error naming the field) and reserves all memory.
  explicit ClockMapper(const ClockMapperOptions& options = {});

  /// Feeds one transfer: the device time of its newest sample [ns, from the unwrapped ticks] and the host
  /// CLOCK_MONOTONIC time it arrived [ns]. Updates the fit. Allocates nothing.
  ClockSampleResult addSample(std::int64_t device_ns, std::int64_t host_receive_ns);

  /// The host time of `device_ns` [ns], or nullopt in kEmpty. Valid for device times inside the window and
  /// shortly after it; far extrapolation multiplies the skew error (0.1 ppm over 10 s = 1 µs).
  std::optional<std::int64_t> toHostNs(std::int64_t device_ns) const;

  ClockMapperState state() const { return state_; }
  bool valid() const { return state_ == ClockMapperState::kValid; }
  /// The current mapping (meaningful unless kEmpty).
  const ClockEstimate& estimate() const { return estimate_; }
  /// host − device at the newest accepted sample [ns] (what a status report shows), 0 in kEmpty.
  std::int64_t offsetNs() const;
  /// Current skew [ppm].
  double skewPpm() const { return estimate_.skewPpm(); }
  /// Device-time span of the window [ns].
  std::int64_t spanNs() const;
  std::size_t windowSize() const { return hull_.size(); }
  std::size_t hullVertices() const { return hull_.vertexCount(); }
  const ClockMapperStats& stats() const { return stats_; }
  const ClockMapperOptions& options() const { return options_; }

  /// Forgets every sample and the last skew (a new device, or the caller's own resynchronisation).
  /// Statistics stay.
  void reset();

 private:
  /// Holds back a sample that disagrees with the window; returns true when enough agree to restart.
  bool holdBack(ClockPoint point);
  void restartFromHeldBack();
  void accept(ClockPoint point);
  void updateEstimate();
  /// (host − device) on the hull's lower envelope at `device_ns`, minus that of `origin` [ns]. Precondition:
  /// at least two vertices.
  double hullExcessNs(std::int64_t device_ns, ClockPoint origin) const;

  ClockMapperOptions options_;
  std::int64_t window_ns_ = 0;
  std::int64_t min_span_ns_ = 0;
  SlidingLowerHull hull_;
  ClockMapperState state_ = ClockMapperState::kEmpty;
  ClockEstimate estimate_;
  double last_valid_skew_ = 0.0;  ///< carried into kWarmingUp after a restart or a long gap
  std::array<ClockPoint, ClockMapperOptions::kMaxStepConfirmSamples> held_back_{};
  std::size_t held_back_count_ = 0;
  ClockMapperStats stats_;
};

}  // namespace vifusion::clock
