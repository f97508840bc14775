#pragma once
// What SyncLine counted, as a plain snapshot (stats() copies it out of atomics, so the service's status
// reporter reads it from its own thread without locking the driver thread).

#include <cstdint>

namespace vifusion::gpio_sync {

enum class SyncLineState : std::uint8_t {
  kClosed,   ///< not started, or stopped
  kRunning,  ///< the driver thread is waiting for edges
  kGone,     ///< the chip disappeared; stop(), then start() again once it is back
  kFailed,   ///< waiting or reading failed otherwise (SyncLine::lastError() says how)
};

/// "closed", "running", "gone", "failed".
const char* syncLineStateName(SyncLineState state);

struct SyncLineStats {
  SyncLineState state = SyncLineState::kClosed;
  std::uint64_t edges_read = 0;      ///< events read from the kernel (= sequence numbers handed out)
  std::uint64_t edges = 0;           ///< SyncEdges pushed into the ring
  std::uint64_t overruns = 0;        ///< good edges lost to a full ring
  std::uint64_t time_backwards = 0;  ///< edges stamped before the previous good edge: dropped
  std::uint64_t bad_event_type = 0;  ///< neither rising nor falling, or a kind not requested: dropped
  std::uint64_t bad_timestamp = 0;   ///< timestamps that do not fit int64 ns or are negative: dropped
  /// Edges stamped after the moment they were read, i.e. not on CLOCK_MONOTONIC (Linux < 5.7 stamps
  /// CLOCK_REALTIME): dropped, since they cannot be compared with camera and IMU times.
  std::uint64_t clock_mismatch = 0;
  std::int64_t last_edge_t_ns = 0;  ///< newest good edge [ns, CLOCK_MONOTONIC]; 0 before the first
  double edge_rate_hz = 0.0;        ///< EdgeRateMeter over good edges, as of the last wait [Hz]

  /// Edges read but not delivered, every reason.
  std::uint64_t dropped() const { return overruns + time_backwards + bad_event_type + bad_timestamp + clock_mismatch; }
};

}  // namespace vifusion::gpio_sync
