#include "sync_checks.hpp"

#include <cmath>
#include <cstdio>
#include <string>

namespace vifusion::synccheck {
namespace {

std::string format(const char* pattern, double a, double b) {
  char text[160];
  std::snprintf(text, sizeof text, pattern, a, b);
  return text;
}

/// value <= limit passes; NaN fails with `missing` as the detail.
CheckResult limitCheck(const char* name, double value, double limit, const char* unit, const char* what,
                       const char* missing) {
  CheckResult check{name, false, value, limit, unit, {}};
  if (std::isnan(value)) {
    check.detail = missing;
    return check;
  }
  check.passed = value <= limit;
  check.detail =
      std::string(what) + format(check.passed ? " %g <= limit %g " : " %g exceeds limit %g ", value, limit) + unit;
  return check;
}

CheckResult rateCheck(const char* name, double rate_hz, double expected_hz, double max_error, const char* missing) {
  const double error = std::abs(rate_hz / expected_hz - 1.0);
  CheckResult check = limitCheck(name, error, max_error, "fraction", "rate error", missing);
  if (!std::isnan(error)) check.detail += format(" (%g Hz, expected %g Hz)", rate_hz, expected_hz);
  return check;
}

}  // namespace

std::vector<CheckResult> evaluateChecks(const SyncReport& report, const SyncCheckOptions& options) {
  constexpr const char* kNoPairs = "no frame paired with a sync edge";
  std::vector<CheckResult> checks;
  const StreamStats* stream = report.stream(kFrameMinusEdge);
  const double offset_ns = stream ? std::abs(stream->offset_median_ns) : kNotMeasured;
  const double jitter_ns = stream ? stream->jitter_p99_ns : kNotMeasured;
  const double drift_ppm = stream ? std::abs(stream->drift_ppm) : kNotMeasured;
  checks.push_back(limitCheck("offset", offset_ns, static_cast<double>(options.max_abs_offset_ns), "ns",
                              "|median frame stamp - edge|", kNoPairs));
  checks.push_back(limitCheck("jitter", jitter_ns, static_cast<double>(options.max_jitter_p99_ns), "ns",
                              "p99 |residual| of frame stamp - edge", "fewer than two frames paired with an edge"));
  checks.push_back(limitCheck("drift", drift_ppm, options.max_abs_drift_ppm, "ppm", "|drift| of frame stamp - edge",
                              "fewer than two frames paired with an edge at distinct times"));
  checks.push_back(limitCheck("dropped", report.dropped.fraction, options.max_dropped_fraction, "fraction",
                              "dropped frames", "no frame paired with an edge and no device frame numbers"));
  checks.push_back(rateCheck("frame_rate", report.frames.rate_hz, options.expected_frame_rate_hz,
                             options.max_rate_error_fraction, "fewer than two frames in increasing time"));
  if (report.imu.samples > 0 || options.require_imu) {
    constexpr const char* kNoImu = "fewer than two IMU samples in increasing time";
    checks.push_back(rateCheck("imu_rate", report.imu.rate_hz, options.expected_imu_rate_hz,
                               options.max_rate_error_fraction, kNoImu));
    checks.push_back(limitCheck("imu_gap", report.imu.largest_gap_ns, static_cast<double>(options.max_imu_gap_ns), "ns",
                                "largest IMU interval", kNoImu));
  }
  return checks;
}

}  // namespace vifusion::synccheck
