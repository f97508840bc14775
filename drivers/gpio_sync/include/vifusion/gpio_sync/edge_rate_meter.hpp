#pragma once
// Edges per second over a sliding time window, for `vifusion status` (a 30 Hz strobe should read 30.0;
// 0 means the camera stopped strobing or the wire is loose).
//
// The meter keeps the newest `capacity` edge times in a ring allocated at construction; add() and rateHz()
// allocate nothing. rateHz(now) takes the n edges inside (now − window, now] and returns
// (n − 1) / (newest − oldest of them): intervals over their span, which is exact for a periodic signal
// whatever the window's phase (n / window would read 30 or 31 for a 30 Hz strobe, by phase). With fewer than
// two edges in the window the rate is 0, so a line that goes silent reads 0 one window later.
//
// Single-threaded: SyncLine drives it on its driver thread and publishes the result through an atomic.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace vifusion::gpio_sync {

class EdgeRateMeter {
 public:
  /// @throws vifusion::Error if capacity < 2 or window_ns <= 0.
  EdgeRateMeter(std::size_t capacity, std::int64_t window_ns);

  /// Records an edge at `t_ns` [ns]. Times must not decrease; an older one is ignored and false returned
  /// (the driver drops such edges before they get here).
  bool add(std::int64_t t_ns);
  /// Edges per second [Hz] in the window ending at `now_ns` [ns]; edges after now_ns count as inside.
  double rateHz(std::int64_t now_ns) const;
  /// Forgets every edge (a re-opened line).
  void reset();

  std::size_t capacity() const { return times_ns_.size(); }
  std::int64_t windowNs() const { return window_ns_; }
  /// Edges currently stored (at most capacity()), in or out of the window.
  std::size_t stored() const { return stored_; }

 private:
  std::vector<std::int64_t> times_ns_;  ///< ring of edge times [ns], sized once
  std::int64_t window_ns_;
  std::size_t next_ = 0;    ///< slot the next add() writes
  std::size_t stored_ = 0;  ///< valid slots, <= capacity
};

}  // namespace vifusion::gpio_sync
