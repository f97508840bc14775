#pragma once
// Optional status LED on a GPIO line (libgpiod v1, Debian bookworm's 1.6): lit while every rule is
// OK. Built without libgpiod, or with no chip configured, it does nothing.

#include <string>

#include "vifusion/config/daemon_config.hpp"

struct gpiod_chip;
struct gpiod_line;

namespace vifusion::health {

class StatusLed {
 public:
  /// Requests the line as an output when health.led_chip is set; throws vifusion::Error naming the
  /// chip and line when that fails, or when the program was built without libgpiod.
  explicit StatusLed(const config::HealthConfig& config);
  ~StatusLed();
  StatusLed(const StatusLed&) = delete;
  StatusLed& operator=(const StatusLed&) = delete;

  void set(bool on);

 private:
  gpiod_chip* chip_ = nullptr;
  gpiod_line* line_ = nullptr;
};

}  // namespace vifusion::health
