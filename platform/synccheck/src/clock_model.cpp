#include "vifusion/synccheck/clock_model.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include "vifusion/core/error.hpp"

namespace vifusion::synccheck {
namespace {

constexpr double kMinStrobes = 2.0;  // a drift needs two frames

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

void require(bool ok, const std::string& value, const char* name, const std::string& condition) {
  if (!ok) throw Error(std::string("clock model field '") + name + "' = " + value + " must be " + condition);
}

void requireNonNegative(std::int64_t value_ns, const char* name) {
  require(value_ns >= 0, std::to_string(value_ns), name, ">= 0");
}

void requireProbability(double p, double max, const char* name) {
  require(std::isfinite(p) && p >= 0.0 && p <= max, number(p), name, "finite and in [0, " + number(max) + "]");
}

void requirePpm(double ppm, const char* name) {
  require(std::isfinite(ppm) && std::abs(ppm) <= ClockModel::kMaxModelPpm, number(ppm), name,
          "finite and within +-" + number(ClockModel::kMaxModelPpm));
}

}  // namespace

std::int64_t ClockModel::framePeriodNs() const { return secondsToNs(1.0 / frame_rate_hz); }

double ClockModel::expectedOffsetNs() const {
  // An exponential's mean is its parameter: the edge is stamped this late on average.
  return static_cast<double>(offset_ns - edge_latency_ns - edge_latency_spread_ns);
}

double ClockModel::expectedJitterStdNs() const {
  // Independent Gaussian event jitter and exponential edge latency (std = mean) add in quadrature.
  return std::hypot(static_cast<double>(jitter_ns), static_cast<double>(edge_latency_spread_ns));
}

void ClockModel::validate() const {
  require(std::isfinite(frame_rate_hz) && frame_rate_hz > 0.0 && frame_rate_hz <= kMaxFrameRateHz,
          number(frame_rate_hz), "frame_rate_hz", "finite and in (0, " + number(kMaxFrameRateHz) + "]");
  require(std::isfinite(duration_s) && duration_s > 0.0 && duration_s <= kMaxDurationS, number(duration_s),
          "duration_s", "finite and in (0, " + number(kMaxDurationS) + "]");
  require(std::floor(duration_s * frame_rate_hz) >= kMinStrobes, number(duration_s), "duration_s",
          "long enough for " + number(kMinStrobes) + " strobes at frame_rate_hz = " + number(frame_rate_hz));
  require(start_ns > 0, std::to_string(start_ns), "start_ns", "> 0");
  const std::int64_t half_period_ns = framePeriodNs() / 2;
  const std::string within_half_period = "within +-" + std::to_string(half_period_ns) + " (half a frame period)";
  require(std::abs(offset_ns) < half_period_ns, std::to_string(offset_ns), "offset_ns", within_half_period);
  requirePpm(drift_ppm, "drift_ppm");
  requireNonNegative(jitter_ns, "jitter_ns");
  requireNonNegative(edge_latency_ns, "edge_latency_ns");
  requireNonNegative(edge_latency_spread_ns, "edge_latency_spread_ns");
  require(strobe_width_ns > 0 && strobe_width_ns < framePeriodNs(), std::to_string(strobe_width_ns), "strobe_width_ns",
          "in (0, " + std::to_string(framePeriodNs()) + ") (one frame period)");
  requireProbability(drop_probability, kMaxLossProbability, "drop_probability");
  requireProbability(duplicate_probability, kMaxLossProbability, "duplicate_probability");
  requireProbability(event_probability, 1.0, "event_probability");
  require(std::abs(kernel_offset_ns) < half_period_ns, std::to_string(kernel_offset_ns), "kernel_offset_ns",
          within_half_period);
  requireNonNegative(kernel_jitter_ns, "kernel_jitter_ns");
  requireNonNegative(device_origin_ns, "device_origin_ns");
  requirePpm(device_skew_ppm, "device_skew_ppm");
  require(std::isfinite(imu_rate_hz) && imu_rate_hz > 0.0 && imu_rate_hz <= kMaxImuRateHz, number(imu_rate_hz),
          "imu_rate_hz", "finite and in (0, " + number(kMaxImuRateHz) + "]");
  requireNonNegative(imu_jitter_ns, "imu_jitter_ns");
  requireNonNegative(mapper_latency_mean_ns, "mapper_latency_mean_ns");
}

}  // namespace vifusion::synccheck
