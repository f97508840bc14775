#pragma once
// The backend for a real camera (built with VIFUSION_WITH_LIVE_DRIVERS): libudev discovery
// (discovery::findCamera), the real system calls (v4l2::SystemDeviceIo), libusb on the adapter board's usbfs
// node (usb_imu::LibusbLink) and udev hotplug events (discovery::HotplugMonitor, created at the first
// follow()).

#include <memory>

#include "vifusion/zr300/zr300_backend.hpp"

namespace vifusion::zr300 {

std::unique_ptr<Zr300Backend> makeSystemBackend();

}  // namespace vifusion::zr300
