#include "vifusion/core/latency_window.hpp"

#include <algorithm>
#include <cmath>

namespace vifusion {
namespace {

/// 1-based nearest rank of percentile `p` (0, 100] among n samples: ⌈p/100 · n⌉.
std::size_t nearestRank(double p, std::size_t n) {
  return std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(p / 100.0 * static_cast<double>(n))));
}

}  // namespace

void LatencyWindow::add(float latency_ms) {
  if (!(latency_ms >= 0.0f)) {  // NaN fails this too
    ++rejected_;
    return;
  }
  samples_[next_] = latency_ms;
  next_ = (next_ + 1) % kCapacity;
  count_ = std::min(count_ + 1, kCapacity);
  last_ms_ = latency_ms;
}

LatencySummary LatencyWindow::summary() const {
  LatencySummary summary;
  summary.samples = count_;
  if (count_ == 0) return summary;
  std::copy_n(samples_.begin(), count_, scratch_.begin());
  const auto at_rank = [&](std::size_t rank) {
    std::nth_element(scratch_.begin(), scratch_.begin() + static_cast<std::ptrdiff_t>(rank - 1),
                     scratch_.begin() + static_cast<std::ptrdiff_t>(count_));
    return scratch_[rank - 1];
  };
  constexpr double kMedian = 50.0, kP99 = 99.0;
  summary.last_ms = last_ms_;
  summary.p50_ms = at_rank(nearestRank(kMedian, count_));
  summary.p99_ms = at_rank(nearestRank(kP99, count_));
  summary.max_ms = *std::max_element(scratch_.begin(), scratch_.begin() + static_cast<std::ptrdiff_t>(count_));
  return summary;
}

}  // namespace vifusion
