#pragma once
// What analyse() (analyse.hpp) finds: per stream pair the offset, jitter and drift; dropped and duplicated
// frames; IMU rate and gaps; the clock mapper's residuals; and the pass/fail checks against
// SyncCheckOptions. Quantities that could not be measured (no pairs, one sample) are NaN, and NaN fails
// every check that reads it. toJson() and savePlot() are what `vifusion synccheck` prints and draws.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "vifusion/synccheck/robust_line_fit.hpp"
#include "vifusion/synccheck/sync_check_options.hpp"

namespace vifusion::synccheck {

inline constexpr double kNotMeasured = std::numeric_limits<double>::quiet_NaN();

/// The stream pairs, a − b, in SyncReport::streams' order.
inline constexpr std::string_view kFrameMinusEdge = "frame_minus_edge";    ///< the stamp SLAM used − its edge
inline constexpr std::string_view kKernelMinusEdge = "kernel_minus_edge";  ///< kernel mid-exposure − edge
inline constexpr std::string_view kDeviceEventMinusEdge = "device_event_minus_edge";  ///< mapped event − edge
inline constexpr std::string_view kFrameMinusKernel = "frame_minus_kernel";           ///< stamp − kernel, every frame

/// One stream pair, a − b (e.g. frame stamp − sync edge), over time.
struct StreamStats {
  std::string name;       ///< one of the k…Minus… names above
  std::size_t count = 0;  ///< samples (one per frame; the second frame on an edge and repeated numbers excluded)
  double offset_mean_ns = kNotMeasured;
  double offset_median_ns = kNotMeasured;
  /// The robust line's value at the first sample [ns]: the offset before drift moved it.
  double offset_at_first_ns = kNotMeasured;
  /// The robust line's slope [ppm]: +40 means a − b grows by 40 µs per second.
  double drift_ppm = kNotMeasured;
  /// Residuals about the robust line [ns]: RMS (n − 2 degrees of freedom), p99 and max of |residual|.
  double jitter_std_ns = kNotMeasured;
  double jitter_p99_ns = kNotMeasured;
  double jitter_max_ns = kNotMeasured;
  LineFit fit;                     ///< offset_ns = fit.at(seconds since first_t_ns)
  std::int64_t first_t_ns = 0;     ///< time of the first sample (the b side for edge pairs, else a) [ns]
  std::vector<std::int64_t> t_ns;  ///< sample times, the plot's x
  std::vector<double> offset_ns;   ///< a − b per sample [ns], the plot's y
};

/// Camera frames: counts, how they were stamped, how they paired.
struct FrameStats {
  std::size_t count = 0;
  std::size_t paired_with_edge = 0;   ///< frames that found their sync edge (duplicates included)
  std::size_t without_edge = 0;       ///< no edge in the window (edge lost, stamp off by > the window)
  std::size_t with_device_event = 0;  ///< device_event_ns != 0
  std::size_t stamped_by_device_event = 0;
  std::size_t stamped_by_kernel = 0;
  std::size_t out_of_order = 0;            ///< t_ns not after the previous frame's
  std::size_t frame_number_backwards = 0;  ///< the device counter went back (a restart, or corruption)
  bool frame_numbers_present = false;      ///< false: every device_frame_number was 0, counter checks skipped
  double rate_hz = kNotMeasured;           ///< 1 / median positive frame interval
};

/// Sync-line edges of the chosen polarity.
struct EdgeStats {
  EdgePolarity polarity = EdgePolarity::kRising;  ///< the polarity paired with (SyncCheckOptions)
  std::size_t count = 0;                          ///< edges in the input, both polarities
  std::size_t used = 0;                           ///< of the chosen polarity, in increasing time
  std::size_t out_of_order = 0;                   ///< of the chosen polarity, not after the previous one: not used
  std::uint64_t lost_by_driver = 0;               ///< sum of the gaps in SyncEdgeTime::sequence
  double period_ns = kNotMeasured;                ///< median interval between used edges, the pairing's frame period
};

struct DropStats {
  /// Edges between the first and the last paired edge that no frame paired with.
  std::size_t edges_without_frame = 0;
  /// Numbers missing between consecutive device frame numbers (0 without numbers).
  std::uint64_t frame_number_gaps = 0;
  /// The larger of the two (each misses what the other sees only in odd cases: an edge lost with the
  /// frame, a counter that skips).
  std::uint64_t dropped = 0;
  /// dropped / (frames that should have come: paired edges' frames + dropped); NaN when nothing paired
  /// and no numbers exist.
  double fraction = kNotMeasured;
};

struct DuplicateStats {
  std::size_t frames_on_one_edge = 0;      ///< frames beyond the first paired with the same edge
  std::size_t repeated_frame_numbers = 0;  ///< a device frame number equal to the previous frame's
};

struct ImuStats {
  std::size_t samples = 0;
  double rate_hz = kNotMeasured;       ///< median of 1/dt over increasing samples (= 1 / median dt)
  double mean_rate_hz = kNotMeasured;  ///< (samples − 1) / (last − first time)
  double median_dt_ns = kNotMeasured;
  std::size_t gaps = 0;                  ///< intervals longer than kImuGapFactor × median dt
  double largest_gap_ns = kNotMeasured;  ///< the longest interval
  std::size_t out_of_order = 0;          ///< samples not after the previous one (dt <= 0)
};

struct ClockResidualStats {
  std::size_t samples = 0;     ///< finite residuals used
  std::size_t non_finite = 0;  ///< NaN or infinite residuals, counted and ignored
  double mean_ns = kNotMeasured;
  double std_ns = kNotMeasured;  ///< sample standard deviation
  double p99_abs_ns = kNotMeasured;
  double max_abs_ns = kNotMeasured;
};

/// One pass/fail check against a SyncCheckOptions limit.
struct CheckResult {
  std::string name;  ///< "offset", "jitter", "drift", "dropped", "frame_rate", "imu_rate", "imu_gap"
  bool passed = false;
  double value = kNotMeasured;  ///< what was measured, in `unit` (NaN: could not be measured → failed)
  double limit = kNotMeasured;  ///< the largest passing value, in `unit`
  std::string unit;             ///< "ns", "ppm", "fraction"
  std::string detail;           ///< one sentence for a person
};

/// Intervals longer than this multiple of the median IMU interval count as gaps (one missing sample
/// makes 2×; 1.5× sits halfway between a jittered regular interval and one sample lost).
inline constexpr double kImuGapFactor = 1.5;

struct SyncReport {
  FrameStats frames;
  EdgeStats edges;
  DropStats dropped;
  DuplicateStats duplicated;
  /// kFrameMinusEdge, kKernelMinusEdge, kDeviceEventMinusEdge, kFrameMinusKernel, in that order.
  std::vector<StreamStats> streams;
  ImuStats imu;
  ClockResidualStats clock_residuals;
  std::vector<CheckResult> checks;
  /// The first few pieces of bad input (ProblemLog::kMaxNotes), each naming its record and field, e.g.
  /// "frame 812 (index 812): t_ns goes backwards by 5000000 ns". The counts above have them all.
  std::vector<std::string> problems;
  bool passed = false;  ///< every check passed

  /// The stream named `name`, or nullptr.
  const StreamStats* stream(std::string_view name) const;
  /// Names of the failed checks, in check order.
  std::vector<std::string> failedChecks() const;
  /// One JSON object, keys stable and documented in sync_report_json.cpp; NaN becomes null.
  std::string toJson() const;
  /// A PNG of every stream's offset over time [ms against s]. @throws vifusion::Error if it cannot be written.
  void savePlot(const std::filesystem::path& path) const;
};

}  // namespace vifusion::synccheck
