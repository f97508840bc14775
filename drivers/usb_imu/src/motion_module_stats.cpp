#include "vifusion/usb_imu/motion_module_stats.hpp"

namespace vifusion::usb_imu {

const char* moduleStateName(ModuleState state) {
  switch (state) {
    case ModuleState::kClosed:
      return "closed";
    case ModuleState::kStreaming:
      return "streaming";
    case ModuleState::kUnplugged:
      return "unplugged";
    case ModuleState::kFailed:
      return "failed";
  }
  return "invalid";
}

}  // namespace vifusion::usb_imu
