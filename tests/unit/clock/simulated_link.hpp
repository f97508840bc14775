#pragma once
// A simulated device clock seen over USB, for the clock tests: a device stamping transfers on its own
// crystal (known offset and skew, optionally a skew change as when the board warms up, optionally a host
// suspend), and a host that receives each transfer after a positive, jittery latency with occasional
// large outliers. Seeded std::mt19937_64, so every run replays exactly.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>

#include "vifusion/core/time.hpp"

namespace vifusion::clock::test {

inline constexpr double kPpm = 1e-6;

struct LinkModel {
  std::int64_t start_device_ns = 5 * kNsPerSecond;              ///< device time of the first transfer
  std::int64_t start_host_ns = 1'234 * kNsPerSecond + 567'891;  ///< true host time of the first transfer
  double skew_ppm = 50.0;                                       ///< host rate / device rate − 1, before any change
  double transfers_per_s = 450.0;                               ///< ZR300: 200 Hz gyro + 250 Hz accel events
  std::int64_t latency_floor_ns = 0;                            ///< constant part of the latency
  double latency_mean_ns = 300'000.0;                           ///< mean of the exponential part
  double outlier_fraction = 0.05;                               ///< transfers hit by a scheduling / bus outlier
  double outlier_min_ns = 1'000'000.0;                          ///< outlier extra delay, uniform in [min, max)
  double outlier_max_ns = 20'000'000.0;
  std::int64_t skew_change_after_ns = -1;  ///< device time since start of a skew change; < 0: none
  double skew_after_change_ppm = 50.0;
  std::int64_t host_pause_after_ns = -1;  ///< device time since start of a host suspend; < 0: none
  std::int64_t host_pause_ns = 0;         ///< how long CLOCK_MONOTONIC stood still while the device counted
};

/// One transfer: its device time, the true host time of that instant and when the host received it.
struct LinkSample {
  std::int64_t device_ns = 0;
  std::int64_t true_host_ns = 0;
  std::int64_t receive_ns = 0;
};

class SimulatedLink {
 public:
  SimulatedLink(const LinkModel& model, std::uint64_t seed)
      : model_(model),
        rng_(seed),
        period_ns_(std::llround(static_cast<double>(kNsPerSecond) / model.transfers_per_s)) {}

  /// The true host time of device time `device_ns` (the mapping a perfect estimator would find).
  std::int64_t trueHostNs(std::int64_t device_ns) const {
    const std::int64_t dx_ns = device_ns - model_.start_device_ns;
    const bool after_pause = model_.host_pause_after_ns >= 0 && dx_ns > model_.host_pause_after_ns;
    return runningHostNs(device_ns) - (after_pause ? model_.host_pause_ns : 0);
  }

  /// The next transfer. Transfers leave the device in order and a delayed one holds up those behind it
  /// (the host sees a burst), so receive times never go back.
  LinkSample next() {
    LinkSample s;
    s.device_ns = model_.start_device_ns + index_ * period_ns_;
    ++index_;
    // While the host sleeps nothing is received: the device times of that stretch never arrive.
    while (inPause(s.device_ns)) s.device_ns = model_.start_device_ns + index_++ * period_ns_;
    s.true_host_ns = trueHostNs(s.device_ns);
    double latency_ns = static_cast<double>(model_.latency_floor_ns) + exponential_(rng_) * model_.latency_mean_ns;
    if (uniform_(rng_) < model_.outlier_fraction) {
      latency_ns += model_.outlier_min_ns + uniform_(rng_) * (model_.outlier_max_ns - model_.outlier_min_ns);
    }
    s.receive_ns = std::max<std::int64_t>(s.true_host_ns + std::llround(latency_ns), last_receive_ns_);
    last_receive_ns_ = s.receive_ns;
    return s;
  }

  std::int64_t periodNs() const { return period_ns_; }
  const LinkModel& model() const { return model_; }

 private:
  bool inPause(std::int64_t device_ns) const {
    const std::int64_t dx_ns = device_ns - model_.start_device_ns;
    return model_.host_pause_after_ns >= 0 && dx_ns > model_.host_pause_after_ns &&
           dx_ns <= model_.host_pause_after_ns + model_.host_pause_ns;
  }

  /// The host time without the suspend: the skew, and the skew change if there is one.
  std::int64_t runningHostNs(std::int64_t device_ns) const {
    const std::int64_t dx_ns = device_ns - model_.start_device_ns;
    if (model_.skew_change_after_ns < 0 || dx_ns <= model_.skew_change_after_ns) {
      return model_.start_host_ns + dx_ns + std::llround(model_.skew_ppm * kPpm * static_cast<double>(dx_ns));
    }
    const std::int64_t change_host_ns = runningHostNs(model_.start_device_ns + model_.skew_change_after_ns);
    const std::int64_t after_ns = dx_ns - model_.skew_change_after_ns;
    return change_host_ns + after_ns +
           std::llround(model_.skew_after_change_ppm * kPpm * static_cast<double>(after_ns));
  }

  LinkModel model_;
  std::mt19937_64 rng_;
  std::exponential_distribution<double> exponential_{1.0};
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  std::int64_t period_ns_;
  std::int64_t index_ = 0;
  std::int64_t last_receive_ns_ = 0;
};

}  // namespace vifusion::clock::test
