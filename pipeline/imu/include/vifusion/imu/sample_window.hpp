#pragma once
// Checks a span of IMU samples before it is integrated over a frame interval [t0_ns, t1_ns]. Problems
// come back as a value naming the sample time (DESIGN.md §3, errors), never integrated silently, and the
// per-frame caller decides (skip the IMU term, report health) without an exception on the frame path:
//  - t1 must be after t0 (kEmptyInterval); the span must not be empty (kNoSamples);
//  - every stamp in the span must be later than the one before it (kDuplicate if equal, kOutOfOrder if
//    earlier): the whole span is checked, as a reordered stream is wrong wherever it is;
//  - a sample at or before t0 and one at or after t1 must exist (kNotCovered), so both frame times are
//    interpolated, never extrapolated;
//  - of the samples that get integrated (the last at or before t0 through the first at or after t1),
//    consecutive ones must be at most max_gap_ns apart (kGap), and every reading must be finite
//    (kNonFinite).

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "vifusion/core/sensor_data.hpp"

namespace vifusion::imu {

enum class ImuSampleProblem { kEmptyInterval, kNoSamples, kOutOfOrder, kDuplicate, kNotCovered, kGap, kNonFinite };

struct ImuSampleIssue {
  ImuSampleProblem problem = ImuSampleProblem::kNoSamples;
  /// The sample at fault; for kEmptyInterval, kNoSamples and kNotCovered the frame time concerned [ns].
  std::int64_t t_ns = 0;
  /// kOutOfOrder, kDuplicate, kGap: the sample before it; kNotCovered: the nearest sample; kEmptyInterval:
  /// the interval's start t0; kNoSamples: the interval's end t1 [ns].
  std::int64_t other_t_ns = 0;
  std::int64_t limit_ns = 0;  ///< kGap: the largest allowed spacing [ns]

  /// What went wrong and where, e.g. "IMU sample at t_ns=1015000000: timestamp goes backwards by 5.000 ms
  /// (previous sample at t_ns=1020000000)". Builds a string: for the error path only.
  std::string message() const;
};

/// Indices into the span of the samples that bracket a frame interval.
struct SampleRange {
  std::size_t first = 0;  ///< the last sample at or before t0
  std::size_t last = 0;   ///< the first sample at or after t1
};

/// Checks `samples` for the frame interval [t0_ns, t1_ns] against the rules above. Returns the first
/// problem, or nullopt and the bracketing range in `range`. Allocates nothing.
[[nodiscard]] std::optional<ImuSampleIssue> checkSampleWindow(std::span<const ImuSample> samples, std::int64_t t0_ns,
                                                              std::int64_t t1_ns, std::int64_t max_gap_ns,
                                                              SampleRange& range);

/// The part of a time-sorted `stream` that a frame interval [t0_ns, t1_ns] needs: from the last sample at
/// or before t0 (the first sample if none) through the first at or after t1 (the last if none), found by
/// binary search, so a caller holding a long stream hands the checks above only what matters. An unsorted
/// stream gives some sub-span, whose checks then report the disorder.
std::span<const ImuSample> bracketingSamples(std::span<const ImuSample> stream, std::int64_t t0_ns,
                                             std::int64_t t1_ns);

}  // namespace vifusion::imu
