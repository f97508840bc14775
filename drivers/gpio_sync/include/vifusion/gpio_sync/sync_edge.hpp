#pragma once
// One edge on the sync line (the camera's strobe or an external trigger), as the driver thread hands it
// to the consumer through SyncLine::edgeRing().

#include <cstdint>

namespace vifusion::gpio_sync {

struct SyncEdge {
  /// When the kernel saw the edge, host CLOCK_MONOTONIC [ns]: stamped in the GPIO interrupt handler, so it
  /// carries the interrupt latency (µs) but none of the delay before the driver thread reads it.
  std::int64_t t_ns = 0;
  /// true: low → high, false: high → low (the line's physical level; no active-low inversion is requested).
  bool rising = true;
  /// Position among the edges read from the kernel on this line since SyncLine::start(), 0-based, counting
  /// the ones the driver dropped (ring full, time going backwards, bad event): a gap between two consecutive
  /// edges the consumer pops is exactly the number lost on our side. Edges lost in the kernel's own queue
  /// (16 events, overflowing only if the thread stalls for 16 edge periods) leave no gap: the v1 uAPI
  /// carries no kernel sequence number.
  std::uint64_t sequence = 0;
};

}  // namespace vifusion::gpio_sync
