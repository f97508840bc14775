#include "vifusion/core/live_imu_feed.hpp"

#include <algorithm>
#include <chrono>
#include <string>
#include <thread>

#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion {
namespace {

constexpr std::size_t kMinWindowCapacity = 16;
constexpr std::int64_t kMaxRetainNs = 60 * kNsPerSecond;
constexpr std::int64_t kMaxWaitNs = 10 * kNsPerSecond;
/// Sleep between two looks at the ring while waiting [ns]: a tenth of the motion module's transfer period,
/// so the wait ends within ≈0.5 ms of the sample's arrival without spinning a core.
constexpr std::int64_t kWaitStepNs = 500'000;

}  // namespace

void LiveImuFeedOptions::validate() const {
  if (window_capacity < kMinWindowCapacity) {
    throw Error("LiveImuFeedOptions.window_capacity = " + std::to_string(window_capacity) + " is below " +
                std::to_string(kMinWindowCapacity) + " samples");
  }
  if (retain_ns < 0 || retain_ns > kMaxRetainNs) {
    throw Error("LiveImuFeedOptions.retain_ns = " + std::to_string(retain_ns) + " is outside [0, 60 s]");
  }
  if (max_wait_ns < 0 || max_wait_ns > kMaxWaitNs) {
    throw Error("LiveImuFeedOptions.max_wait_ns = " + std::to_string(max_wait_ns) + " is outside [0, 10 s]");
  }
}

LiveImuFeed::LiveImuFeed(SpscRing<ImuSample>& ring, const LiveImuFeedOptions& options)
    : ring_(ring), options_(options) {
  options_.validate();
  window_.reserve(options_.window_capacity);
}

bool LiveImuFeed::drainUntil(std::int64_t t_imu_ns) {
  while (ring_.tryPop(incoming_)) {
    if (!window_.empty() && incoming_.t_ns <= window_.back().t_ns) {
      ++stats_.out_of_order;
      continue;
    }
    if (window_.size() == options_.window_capacity) {
      // Make room for a quarter of the window at once, so a steady overflow erases rarely.
      const std::size_t drop = options_.window_capacity / 4;
      window_.erase(window_.begin(), window_.begin() + static_cast<std::ptrdiff_t>(drop));
      stats_.window_drops += drop;
    }
    window_.push_back(incoming_);
    ++stats_.samples;
  }
  return !window_.empty() && window_.back().t_ns >= t_imu_ns;
}

void LiveImuFeed::trimBefore(std::int64_t t_keep_ns) {
  // Keep the last sample at or before t_keep_ns: it brackets the retained interval from below.
  const auto after = std::upper_bound(window_.begin(), window_.end(), t_keep_ns,
                                      [](std::int64_t t, const ImuSample& sample) { return t < sample.t_ns; });
  if (after - window_.begin() > 1) window_.erase(window_.begin(), after - 1);
}

std::span<const ImuSample> LiveImuFeed::samplesThrough(std::int64_t t_cam_ns) {
  ++stats_.frames;
  const std::int64_t t_imu_ns = t_cam_ns + options_.time_shift_cam_imu_ns;
  if (!drainUntil(t_imu_ns)) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::nanoseconds(options_.max_wait_ns);
    bool covered = false;
    while (!covered && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::nanoseconds(kWaitStepNs));
      covered = drainUntil(t_imu_ns);
    }
    if (!covered) ++stats_.late_frames;
  }
  trimBefore((have_previous_ ? previous_t_imu_ns_ : t_imu_ns) - options_.retain_ns);
  previous_t_imu_ns_ = t_imu_ns;
  have_previous_ = true;
  return window_;
}

}  // namespace vifusion
