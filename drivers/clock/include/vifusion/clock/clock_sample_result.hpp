#pragma once
// What ClockMapper::addSample() did with one (device_ns, host_ns) pair. Rejections come back as a value
// naming the field and what is wrong (DESIGN.md §3, errors), never as an exception on the per-sample
// path; the message string is built only when the caller asks for it.

#include <cstdint>
#include <string>

namespace vifusion::clock {

enum class ClockSampleOutcome {
  kAccepted,             ///< added to the window
  kRestarted,            ///< confirmed a clock step: the window restarted from the held-back samples and this one
  kOutOfRange,           ///< device_ns or host_ns outside [0, kMaxClockTimeNs]: dropped
  kDeviceNotIncreasing,  ///< device_ns not after the window's newest: held back as a possible clock step
  kHostBackwards,        ///< host_ns before the window's newest host_ns: dropped
  kEarly,                ///< host_ns earlier than the mapping allows (max_early_ns): held back likewise
};

struct ClockSampleResult {
  ClockSampleOutcome outcome = ClockSampleOutcome::kAccepted;
  std::int64_t device_ns = 0;  ///< the sample as given [ns]
  std::int64_t host_ns = 0;    ///< the sample as given, before fixed_latency_ns is taken off [ns]
  /// kDeviceNotIncreasing: the newest accepted device_ns; kHostBackwards: the newest accepted host_ns (as
  /// given); kEarly: the host time the mapping predicts (with fixed_latency_ns added back), so that
  /// reference_ns − host_ns is how early it came; kRestarted: how many held-back samples the restart used.
  std::int64_t reference_ns = 0;

  /// True for kAccepted and kRestarted: the sample is in the window.
  bool accepted() const {
    return outcome == ClockSampleOutcome::kAccepted || outcome == ClockSampleOutcome::kRestarted;
  }

  /// What happened and why, e.g. "clock sample device_ns=5000000 host_ns=9000000: device_ns does not
  /// increase (2.000 ms before the previous sample's 7000000); dropped". Builds a string: for the error
  /// path only.
  std::string message() const;
};

}  // namespace vifusion::clock
