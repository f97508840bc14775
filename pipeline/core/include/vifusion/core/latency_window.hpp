#pragma once
// The latency of the last frames, for a service's status: a fixed window of the newest kCapacity samples
// [ms] and their median, 99th percentile (nearest rank: the smallest sample with at least 99 % of the
// window at or below it) and maximum. Fixed storage: adding and summarising never allocate. One thread.

#include <array>
#include <cstddef>

namespace vifusion {

struct LatencySummary {
  float last_ms = 0.0f;
  float p50_ms = 0.0f;
  float p99_ms = 0.0f;
  float max_ms = 0.0f;
  std::size_t samples = 0;  ///< in the window (0: the rest is 0)
};

class LatencyWindow {
 public:
  /// 10 s at a camera's 30 Hz.
  static constexpr std::size_t kCapacity = 300;

  /// Adds one sample [ms], replacing the oldest once the window is full. NaN and negative samples (a
  /// clock that went backwards) are kept out and counted.
  void add(float latency_ms);
  LatencySummary summary() const;
  std::size_t rejected() const { return rejected_; }

 private:
  std::array<float, kCapacity> samples_{};
  std::size_t count_ = 0;  ///< samples added, up to kCapacity
  std::size_t next_ = 0;   ///< where the next sample goes
  float last_ms_ = 0.0f;
  std::size_t rejected_ = 0;
  mutable std::array<float, kCapacity> scratch_{};  ///< summary()'s sorting space
};

}  // namespace vifusion
