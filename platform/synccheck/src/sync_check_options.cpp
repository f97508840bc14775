#include "vifusion/synccheck/sync_check_options.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include "vifusion/core/error.hpp"

namespace vifusion::synccheck {
namespace {

constexpr int kMaxFrameNumberBits = 32;  // CameraFrameTimes::device_frame_number is a u32

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

void require(bool ok, const std::string& value, const char* name, const std::string& condition) {
  if (!ok) throw Error(std::string("synccheck option '") + name + "' = " + value + " must be " + condition);
}

void requireRate(double rate_hz, const char* name) {
  require(std::isfinite(rate_hz) && rate_hz > 0.0 && rate_hz <= SyncCheckOptions::kMaxRateHz, number(rate_hz), name,
          "finite and in (0, " + number(SyncCheckOptions::kMaxRateHz) + "]");
}

}  // namespace

std::string_view edgePolarityName(EdgePolarity polarity) {
  return polarity == EdgePolarity::kRising ? "rising" : "falling";
}

std::optional<EdgePolarity> parseEdgePolarity(std::string_view text) {
  if (text == "rising") return EdgePolarity::kRising;
  if (text == "falling") return EdgePolarity::kFalling;
  return std::nullopt;
}

std::int64_t SyncCheckOptions::framePeriodNs() const { return secondsToNs(1.0 / expected_frame_rate_hz); }

void SyncCheckOptions::validate() const {
  requireRate(expected_frame_rate_hz, "expected_frame_rate_hz");
  requireRate(expected_imu_rate_hz, "expected_imu_rate_hz");
  require(edge_polarity == EdgePolarity::kRising || edge_polarity == EdgePolarity::kFalling,
          std::to_string(static_cast<int>(edge_polarity)), "edge_polarity", "rising or falling");
  require(frame_number_bits >= kMinFrameNumberBits && frame_number_bits <= kMaxFrameNumberBits,
          std::to_string(frame_number_bits), "frame_number_bits",
          "in [" + std::to_string(kMinFrameNumberBits) + ", " + std::to_string(kMaxFrameNumberBits) + "]");
  require(std::isfinite(pairing_window_fraction) && pairing_window_fraction > 0.0 && pairing_window_fraction < 0.5,
          number(pairing_window_fraction), "pairing_window_fraction", "finite and in (0, 0.5)");
  require(max_abs_offset_ns >= 0, std::to_string(max_abs_offset_ns), "max_abs_offset_ns", ">= 0");
  require(max_jitter_p99_ns >= 0, std::to_string(max_jitter_p99_ns), "max_jitter_p99_ns", ">= 0");
  require(std::isfinite(max_abs_drift_ppm) && max_abs_drift_ppm >= 0.0, number(max_abs_drift_ppm), "max_abs_drift_ppm",
          "finite and >= 0");
  require(std::isfinite(max_dropped_fraction) && max_dropped_fraction >= 0.0 && max_dropped_fraction <= 1.0,
          number(max_dropped_fraction), "max_dropped_fraction", "finite and in [0, 1]");
  require(max_imu_gap_ns > 0, std::to_string(max_imu_gap_ns), "max_imu_gap_ns", "> 0");
  require(std::isfinite(max_rate_error_fraction) && max_rate_error_fraction > 0.0 && max_rate_error_fraction < 1.0,
          number(max_rate_error_fraction), "max_rate_error_fraction", "finite and in (0, 1)");
}

}  // namespace vifusion::synccheck
