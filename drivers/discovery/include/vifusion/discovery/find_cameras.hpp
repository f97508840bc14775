#pragma once
// Finds every ZR300 through libudev (sysfs and the udev database), without opening any device.
//
// USB devices 8086:0acb (camera) and 8086:0ad0 (adapter board) are paired by their parent, the ZR300's
// internal hub. A video4linux node belongs to the USB device above it; its sysfs parent is the UVC
// function's VideoControl interface, whose bInterfaceNumber orders the camera's capture nodes into IR,
// depth, colour (as librealsense's V4L2 back end does). Nodes whose sysfs `index` is not
// kCaptureNodeIndex (UVC metadata nodes) are skipped and counted.

#include "vifusion/discovery/zr300_camera.hpp"

namespace vifusion::discovery {

/// Scans the system now. Incomplete cameras (no video nodes, no adapter) are listed as found, so that
/// selection can name what is missing. Sysfs values that do not parse (a busnum that is not a number, a
/// bInterfaceNumber that is not hex) leave the field at its "unknown" value (0 or −1) instead of failing.
/// @throws DiscoveryError(kUdevUnavailable) when libudev cannot be initialised or cannot enumerate.
CameraScan findCameras();

}  // namespace vifusion::discovery
