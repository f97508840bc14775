#include "vifusion/usb_imu/usb_link.hpp"

namespace vifusion::usb_imu {

std::string_view usbStatusName(UsbStatus status) {
  switch (status) {
    case UsbStatus::kOk:
      return "ok";
    case UsbStatus::kTimeout:
      return "timeout";
    case UsbStatus::kNoDevice:
      return "no_device";
    case UsbStatus::kAccessDenied:
      return "access_denied";
    case UsbStatus::kBusy:
      return "busy";
    case UsbStatus::kOverflow:
      return "overflow";
    case UsbStatus::kIoError:
      return "io_error";
  }
  return "invalid";
}

}  // namespace vifusion::usb_imu
