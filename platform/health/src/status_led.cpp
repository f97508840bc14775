#include "status_led.hpp"

#include <cerrno>
#include <cstring>

#include "vifusion/core/error.hpp"

#if VIFUSION_HAVE_GPIOD
#include <gpiod.h>
#endif

namespace vifusion::health {

StatusLed::StatusLed(const config::HealthConfig& config) {
  if (config.led_chip.empty()) return;
#if VIFUSION_HAVE_GPIOD
  const std::string where = "health.led_chip '" + config.led_chip + "' line " + std::to_string(config.led_line);
  chip_ = gpiod_chip_open_lookup(config.led_chip.c_str());
  if (chip_ == nullptr) throw Error(where + ": cannot open the chip: " + std::strerror(errno));
  line_ = gpiod_chip_get_line(chip_, static_cast<unsigned>(config.led_line));
  if (line_ == nullptr || gpiod_line_request_output(line_, "vifusion-health", 0) != 0) {
    const int error = errno;
    gpiod_chip_close(chip_);
    chip_ = nullptr;
    throw Error(where + ": cannot request the line as an output: " + std::strerror(error));
  }
#else
  throw Error("health.led_chip is set but vifusion-health was built without libgpiod (install libgpiod-dev)");
#endif
}

StatusLed::~StatusLed() {
#if VIFUSION_HAVE_GPIOD
  if (line_ != nullptr) gpiod_line_release(line_);
  if (chip_ != nullptr) gpiod_chip_close(chip_);
#endif
}

void StatusLed::set(bool on) {
#if VIFUSION_HAVE_GPIOD
  if (line_ != nullptr) static_cast<void>(gpiod_line_set_value(line_, on ? 1 : 0));
#else
  static_cast<void>(on);
#endif
}

}  // namespace vifusion::health
