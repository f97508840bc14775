#pragma once
// Settings of SyncLine (sync_line.hpp), each defined once, with the range validate() enforces.

#include <cstddef>
#include <cstdint>
#include <string>

#include "vifusion/core/time.hpp"
#include "vifusion/gpio_sync/edge_detection.hpp"

namespace vifusion::gpio_sync {

struct SyncLineOptions {
  /// The GPIO chip: a name under /dev ("gpiochip0", what `gpiodetect` lists) or an absolute path
  /// ("/dev/gpiochip0", or a udev symlink such as "/dev/gpio-camera"). Non-empty; a name holds no '/'.
  std::string chip = "gpiochip0";
  /// Line offset on that chip (what `gpioinfo` numbers), [0, kMaxLineOffset]. The chip's own line count is
  /// checked when the line is opened.
  int line_offset = 0;
  /// Which edges are reported. Rising: one edge per strobe pulse (start of exposure).
  EdgeDetection edges = EdgeDetection::kRising;
  /// SyncEdges the ring holds for the consumer [edges], >= 1. 512 is 17 s of a 30 Hz strobe, 4 s of both
  /// edges at 60 Hz: a consumer stalled longer has lost tracking anyway; beyond it edges are overruns.
  std::size_t ring_capacity = 512;
  /// How long one wait for an edge lasts [ms], (0, kMaxWaitTimeoutMs]: bounds how soon stop() is seen and
  /// how stale the published edge rate gets on a silent line.
  int wait_timeout_ms = 100;
  /// Sliding window of the edge-rate meter [ns], (0, kMaxRateWindowNs]: 1 s shows a 30 Hz strobe as 30.0.
  std::int64_t rate_window_ns = kNsPerSecond;
  /// Edge times the meter keeps [edges], [2, kMaxRateCapacity]. When more edges than this fall in the
  /// window the rate is taken over the newest ones only (still exact for a periodic signal).
  std::size_t rate_capacity = 256;

  /// Offsets are u32 in the uAPI, but no chip has more than a few hundred lines; a larger value is a
  /// mistake (a sysfs global GPIO number instead of a chip offset, a sign error).
  static constexpr int kMaxLineOffset = 65535;
  static constexpr int kMaxWaitTimeoutMs = 1000;
  static constexpr std::int64_t kMaxRateWindowNs = 60 * kNsPerSecond;
  static constexpr std::size_t kMaxRateCapacity = 65536;

  /// @throws vifusion::Error naming the first bad field, its value and the allowed range.
  void validate() const;
};

}  // namespace vifusion::gpio_sync
