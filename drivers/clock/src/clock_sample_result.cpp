#include "vifusion/clock/clock_sample_result.hpp"

#include <cstdio>

#include "vifusion/clock/sliding_lower_hull.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion::clock {
namespace {

std::string milliseconds(std::int64_t t_ns) {
  char text[40];
  std::snprintf(text, sizeof text, "%.3f ms", static_cast<double>(t_ns) / static_cast<double>(kNsPerMillisecond));
  return text;
}

}  // namespace

std::string ClockSampleResult::message() const {
  const std::string sample =
      "clock sample device_ns=" + std::to_string(device_ns) + " host_ns=" + std::to_string(host_ns) + ": ";
  switch (outcome) {
    case ClockSampleOutcome::kAccepted:
      return sample + "accepted";
    case ClockSampleOutcome::kRestarted:
      return sample + "clock step confirmed by " + std::to_string(reference_ns) +
             " samples in a row that disagree with the window (host suspend or device clock restart); mapping "
             "restarted from them";
    case ClockSampleOutcome::kOutOfRange:
      return sample + "device_ns or host_ns is outside [0, " + std::to_string(kMaxClockTimeNs) + "]; dropped";
    case ClockSampleOutcome::kDeviceNotIncreasing:
      return sample + "device_ns does not increase (" + milliseconds(reference_ns - device_ns) +
             " before the previous sample's " + std::to_string(reference_ns) +
             "); held back as a possible clock step, dropped unless the next samples confirm one";
    case ClockSampleOutcome::kHostBackwards:
      return sample + "host_ns goes backwards (" + milliseconds(reference_ns - host_ns) +
             " before the previous sample's " + std::to_string(reference_ns) + "); dropped";
    case ClockSampleOutcome::kEarly:
      return sample + "host_ns arrives " + milliseconds(reference_ns - host_ns) +
             " earlier than the mapping allows (latency cannot be negative); held back as a possible clock "
             "step, dropped unless the next samples confirm one";
  }
  return sample + "unknown outcome";
}

}  // namespace vifusion::clock
