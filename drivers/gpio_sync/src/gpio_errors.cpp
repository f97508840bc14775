#include "vifusion/gpio_sync/gpio_errors.hpp"

#include <cerrno>
#include <cstring>

namespace vifusion::gpio_sync {
namespace {

constexpr std::string_view kDeviceDirectory = "/dev/";

std::string lineName(std::string_view chip, unsigned line_offset) {
  return std::string(chip) + " line " + std::to_string(line_offset);
}

}  // namespace

std::string chipPath(std::string_view chip) {
  if (!chip.empty() && chip.front() == '/') return std::string(chip);
  return std::string(kDeviceDirectory) + std::string(chip);
}

std::string describeChipOpenFailure(std::string_view chip, int error_number) {
  const std::string detail = chipPath(chip) + ": " + std::strerror(error_number);
  std::string what;
  switch (error_number) {
    case ENOENT:
      what = "no such GPIO chip (" + detail + "; `gpiodetect` lists the chips)";
      break;
    case EACCES:
    case EPERM:
      what = "permission denied (" + detail +
             "; give the service user access to the chip through the udev rule and its group)";
      break;
    case ENOTTY:  // libgpiod: a character device of another subsystem (/dev/null)
    case ENODEV:
    case EISDIR:
      what = "not a GPIO chip (" + detail + ")";
      break;
    default:
      what = "cannot open the GPIO chip (" + detail + ")";
      break;
  }
  return std::string(chip) + ": " + what;
}

std::string describeLineOutOfRange(std::string_view chip, unsigned line_offset, unsigned line_count) {
  std::string out = lineName(chip, line_offset) + ": out of range, the chip has " + std::to_string(line_count) +
                    (line_count == 1 ? " line" : " lines");
  if (line_count > 0) out += " (offsets 0 to " + std::to_string(line_count - 1) + ")";
  return out;
}

std::string describeRequestFailure(std::string_view chip, unsigned line_offset, EdgeDetection edges, int error_number,
                                   std::string_view holder) {
  std::string out =
      lineName(chip, line_offset) + ": cannot request " + std::string(edgeDetectionName(edges)) + " edge events: ";
  if (error_number == EBUSY) {
    out += "the line is busy";
    if (!holder.empty()) out += ", held by \"" + std::string(holder) + "\"";
    out += " (" + std::string(std::strerror(error_number)) + ")";
  } else {
    out += std::strerror(error_number);
  }
  return out;
}

}  // namespace vifusion::gpio_sync
