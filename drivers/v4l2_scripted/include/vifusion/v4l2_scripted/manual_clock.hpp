#pragma once
// The scripted device's time: a CLOCK_MONOTONIC stand-in that moves only when told to. A poll with a timeout
// advances it (to the next scripted event or by the whole timeout), so a 30 s stream replays in as much real
// time as the work takes, with no sleeping, and every timestamp is reproducible.

#include <atomic>
#include <cstdint>

namespace vifusion::v4l2_scripted {

class ManualClock {
 public:
  /// Starts at a plausible uptime (1000 s) rather than 0, so that "timestamp is zero" checks stay meaningful.
  static constexpr std::int64_t kDefaultStartNs = 1'000'000'000'000;

  explicit ManualClock(std::int64_t start_ns = kDefaultStartNs) : now_ns_(start_ns) {}

  std::int64_t nowNs() const { return now_ns_.load(std::memory_order_acquire); }
  /// Moves to t_ns if that is later; time never goes back.
  void advanceTo(std::int64_t t_ns) {
    std::int64_t now = now_ns_.load(std::memory_order_acquire);
    while (t_ns > now && !now_ns_.compare_exchange_weak(now, t_ns, std::memory_order_acq_rel)) {
    }
  }
  void advanceBy(std::int64_t dt_ns) { advanceTo(nowNs() + dt_ns); }

 private:
  std::atomic<std::int64_t> now_ns_;
};

}  // namespace vifusion::v4l2_scripted
