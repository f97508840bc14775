#include "vifusion/service/systemd_notifier.hpp"

#include <systemd/sd-daemon.h>

#include <cstdio>
#include <string>

namespace vifusion::service {

SystemdNotifier::SystemdNotifier() {
  std::uint64_t usec = 0;
  if (sd_watchdog_enabled(0, &usec) > 0) watchdog_period_ns_ = static_cast<std::int64_t>(usec) * 1000 / 2;
}

// sd_notify returns 0 without $NOTIFY_SOCKET and < 0 on a send error; a lost notification is not a
// reason to stop the service (systemd acts on the missing READY/WATCHDOG itself), so results are ignored.
void SystemdNotifier::ready() const { static_cast<void>(sd_notify(0, "READY=1")); }
void SystemdNotifier::stopping() const { static_cast<void>(sd_notify(0, "STOPPING=1")); }
void SystemdNotifier::watchdog() const { static_cast<void>(sd_notify(0, "WATCHDOG=1")); }

void SystemdNotifier::status(const char* text) const {
  char line[256];
  std::snprintf(line, sizeof(line), "STATUS=%s", text);
  static_cast<void>(sd_notify(0, line));
}

void SystemdNotifier::extendTimeout(std::uint64_t usec) const {
  char line[64];
  std::snprintf(line, sizeof(line), "EXTEND_TIMEOUT_USEC=%llu", static_cast<unsigned long long>(usec));
  static_cast<void>(sd_notify(0, line));
}

}  // namespace vifusion::service
