#pragma once
// Kernel buffer timestamps → the mid-exposure times the pipeline uses (DESIGN.md §3, "camera time is
// mid-exposure").
//
// uvcvideo stamps each buffer from CLOCK_MONOTONIC (V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC) at the start of
// exposure (V4L2_BUF_FLAG_TSTAMP_SRC_SOE; kernel commit c767492a58fd, sensors.md §1.7), so
//   SOE:  t_mid = t_stamp + exposure / 2
// Drivers that stamp at the end of the frame (V4L2_BUF_FLAG_TSTAMP_SRC_EOF, the flag value 0, also what a
// driver that says nothing reports) stamp after exposure and readout:
//   EOF:  t_mid = t_stamp − readout − exposure / 2
// Refused (counted, reason in the ProblemText, never thrown): a clock other than CLOCK_MONOTONIC (COPY or
// UNKNOWN would not compare with the IMU's host times), a zero stamp, a stamp that does not move forward,
// a mid-exposure time that does not move forward (exposure grew faster than time passed), a negative
// exposure or readout.

#include <cstdint>
#include <optional>

#include "vifusion/v4l2/problem_text.hpp"

namespace vifusion::v4l2 {

/// What the caller knows about the exposure of the frame being stamped.
struct ExposureTiming {
  std::int64_t exposure_ns = 0;  ///< integration time [ns], ≥ 0 (from the camera's exposure control)
  std::int64_t readout_ns = 0;   ///< end of exposure → end-of-frame stamp [ns], ≥ 0; unused for SOE stamps
};

class MidExposureClock {
 public:
  /// Mid-exposure time [ns, CLOCK_MONOTONIC] of a buffer with V4L2 `buffer_flags` stamped at `t_stamp_ns`,
  /// or nullopt when refused (then `problem` says which field is wrong and how).
  std::optional<std::int64_t> midExposureNs(std::uint32_t buffer_flags, std::int64_t t_stamp_ns,
                                            const ExposureTiming& timing, ProblemText& problem);
  /// Forgets the previous frame (after a restart of the stream).
  void reset() { have_previous_ = false; }

  std::int64_t refusals() const { return refusals_; }

 private:
  std::optional<std::int64_t> refuse() {
    ++refusals_;
    return std::nullopt;
  }

  bool have_previous_ = false;
  std::int64_t previous_stamp_ns_ = 0;
  std::int64_t previous_mid_ns_ = 0;
  std::int64_t refusals_ = 0;
};

}  // namespace vifusion::v4l2
