#pragma once
// Errors from a V4L2 node at start-up or configuration time. They carry the errno so that the live source
// can tell a camera that went away (wait for the hotplug event) from one that is misconfigured (give up).

#include <string>

#include "vifusion/core/error.hpp"

namespace vifusion::v4l2 {

/// True for the errno values a V4L2/UVC node returns once its USB device is gone: ENODEV (node
/// unregistered), ENXIO, and EIO (uvcvideo marks the queue in error when the device disconnects).
bool isDeviceGoneErrno(int error_number);

/// "ENODEV (No such device)": the symbolic name first, because that is what people search for.
std::string errnoText(int error_number);
/// "ENODEV": the symbolic name alone, from a static table (no allocation: usable on the per-frame path).
const char* errnoName(int error_number);

/// A failed call on a device node; what() names the node, the call and the errno.
class DeviceError : public Error {
 public:
  DeviceError(const std::string& message, int error_number)
      : Error(message + ": " + errnoText(error_number)), error_number_(error_number) {}

  int errorNumber() const { return error_number_; }
  /// The device was unplugged (or its node vanished) rather than refusing the request.
  bool deviceGone() const { return isDeviceGoneErrno(error_number_); }

 private:
  int error_number_ = 0;
};

}  // namespace vifusion::v4l2
