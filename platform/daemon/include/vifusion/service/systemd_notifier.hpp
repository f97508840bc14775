#pragma once
// The systemd notify protocol (sd_notify(3)) for Type=notify units: READY=1, STATUS=, WATCHDOG=1,
// EXTEND_TIMEOUT_USEC=, STOPPING=1. Without $NOTIFY_SOCKET (run by hand, in tests) every call is a
// no-op, so the programs never need to know whether systemd started them.

#include <cstdint>

namespace vifusion::service {

class SystemdNotifier {
 public:
  /// Reads the unit's watchdog interval ($WATCHDOG_USEC, for this process only).
  SystemdNotifier();

  void ready() const;
  void stopping() const;
  /// One human-readable line for `systemctl status`.
  void status(const char* text) const;
  /// Pet the watchdog: call only after real progress (platform.md §3.1), never from a bare timer.
  void watchdog() const;
  /// Asks systemd for `usec` more start-up (or shutdown) time from now [µs].
  void extendTimeout(std::uint64_t usec) const;

  /// How often to pet the watchdog: half its timeout [ns]; 0 when the unit has no watchdog.
  std::int64_t watchdogPeriodNs() const { return watchdog_period_ns_; }

 private:
  std::int64_t watchdog_period_ns_ = 0;
};

}  // namespace vifusion::service
