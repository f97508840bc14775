#include "vifusion/clock/clock_mapper_options.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion::clock {
namespace {

constexpr double kMaxWindowS = 3600.0;                     // an hour: beyond it drift is not linear anyway
constexpr std::int64_t kMaxFixedLatencyNs = kNsPerSecond;  // a "fixed latency" of a second is a mistake
constexpr std::size_t kMinSamplesForFit = 2;               // a line needs two points

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

void require(bool ok, const std::string& value, const char* name, const std::string& condition) {
  if (!ok) throw Error(std::string("clock mapper option '") + name + "' = " + value + " must be " + condition);
}

}  // namespace

std::int64_t ClockMapperOptions::windowNs() const { return secondsToNs(window_s); }

std::int64_t ClockMapperOptions::minSpanNs() const { return secondsToNs(min_span_s); }

void ClockMapperOptions::validate() const {
  require(std::isfinite(window_s) && window_s > 0.0 && window_s <= kMaxWindowS, number(window_s), "window_s",
          "finite and in (0, " + number(kMaxWindowS) + "]");
  require(std::isfinite(min_span_s) && min_span_s > 0.0 && min_span_s < window_s, number(min_span_s), "min_span_s",
          "finite and in (0, window_s = " + number(window_s) + ")");
  require(min_samples >= kMinSamplesForFit, std::to_string(min_samples), "min_samples",
          ">= " + std::to_string(kMinSamplesForFit));
  require(window_samples >= min_samples, std::to_string(window_samples), "window_samples",
          ">= min_samples = " + std::to_string(min_samples));
  require(fixed_latency_ns >= 0 && fixed_latency_ns < kMaxFixedLatencyNs, std::to_string(fixed_latency_ns),
          "fixed_latency_ns", "in [0, " + std::to_string(kMaxFixedLatencyNs) + ")");
  require(max_early_ns > 0, std::to_string(max_early_ns), "max_early_ns", "> 0");
  require(step_confirm_samples >= 1 && step_confirm_samples <= kMaxStepConfirmSamples,
          std::to_string(step_confirm_samples), "step_confirm_samples",
          "in [1, " + std::to_string(kMaxStepConfirmSamples) + "]");
}

}  // namespace vifusion::clock
