#include "vifusion/gpio_sync/edge_rate_meter.hpp"

#include <limits>
#include <string>

#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion::gpio_sync {
namespace {

constexpr std::size_t kMinCapacity = 2;  // a rate needs one interval, so two edges

std::size_t checkedCapacity(std::size_t capacity) {
  if (capacity < kMinCapacity) {
    throw Error("EdgeRateMeter: capacity must be >= " + std::to_string(kMinCapacity) + ", got " +
                std::to_string(capacity));
  }
  return capacity;
}

std::int64_t checkedWindow(std::int64_t window_ns) {
  if (window_ns <= 0) throw Error("EdgeRateMeter: window_ns must be > 0, got " + std::to_string(window_ns));
  return window_ns;
}

}  // namespace

EdgeRateMeter::EdgeRateMeter(std::size_t capacity, std::int64_t window_ns)
    : times_ns_(checkedCapacity(capacity), 0), window_ns_(checkedWindow(window_ns)) {}

bool EdgeRateMeter::add(std::int64_t t_ns) {
  const std::size_t capacity = times_ns_.size();
  if (stored_ > 0 && t_ns < times_ns_[(next_ + capacity - 1) % capacity]) return false;
  times_ns_[next_] = t_ns;
  next_ = (next_ + 1) % capacity;
  if (stored_ < capacity) ++stored_;
  return true;
}

double EdgeRateMeter::rateHz(std::int64_t now_ns) const {
  if (stored_ < kMinCapacity) return 0.0;
  const std::size_t capacity = times_ns_.size();
  // now − window would overflow for a `now` near the int64 minimum; then every stored edge is inside.
  constexpr std::int64_t kEarliestNs = std::numeric_limits<std::int64_t>::min();
  const std::int64_t window_start_ns = now_ns >= kEarliestNs + window_ns_ ? now_ns - window_ns_ : kEarliestNs;
  const std::int64_t newest_ns = times_ns_[(next_ + capacity - 1) % capacity];
  if (newest_ns <= window_start_ns) return 0.0;
  std::size_t in_window = 1;
  std::int64_t oldest_ns = newest_ns;
  for (std::size_t back = 2; back <= stored_; ++back) {
    const std::int64_t t_ns = times_ns_[(next_ + capacity - back) % capacity];
    if (t_ns <= window_start_ns) break;
    oldest_ns = t_ns;
    ++in_window;
  }
  if (in_window < kMinCapacity || newest_ns == oldest_ns) return 0.0;
  return static_cast<double>(in_window - 1) / nsToSeconds(newest_ns - oldest_ns);
}

void EdgeRateMeter::reset() {
  next_ = 0;
  stored_ = 0;
}

}  // namespace vifusion::gpio_sync
