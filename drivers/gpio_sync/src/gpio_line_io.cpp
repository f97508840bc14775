#include "vifusion/gpio_sync/gpio_line_io.hpp"

namespace vifusion::gpio_sync {

std::string_view lineStatusName(LineStatus status) {
  switch (status) {
    case LineStatus::kEvents:
      return "events";
    case LineStatus::kTimeout:
      return "timeout";
    case LineStatus::kGone:
      return "gone";
    case LineStatus::kError:
      return "error";
  }
  return "invalid";
}

}  // namespace vifusion::gpio_sync
