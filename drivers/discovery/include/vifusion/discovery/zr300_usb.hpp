#pragma once
// USB identity and Linux device nodes of the Intel RealSense ZR300 (sensors.md §1.1, §1.7; librealsense
// v1.12.4 src/uvc.h, src/ds-device.h, src/uvc-v4l2.cpp), and the names systemd/99-vifusion.rules gives them.
//
// The ZR300 is two USB devices behind one internal hub (seen on real units: the hub at 4-2, the camera at
// 4-2.1, the adapter at 4-2.2):
//   8086:0acb  DS4 camera, "Intel RealSense 3D Camera ZR300" by "Intel Corp", iSerialNumber "SN_<digits>".
//              Three UVC functions, each a VideoControl interface (bInterfaceNumber 0, 2, 4) with one
//              streaming interface; in ascending bInterfaceNumber: IR, depth, colour.
//   8086:0ad0  adapter board, "CX3-UVC" by "Cypress", no iSerialNumber. A UVC function on interface 0 (the
//              fisheye camera) and the vendor interface 2 of the motion module (IMU events, commands,
//              calibration EEPROM), which libusb opens through /dev/bus/usb/BBB/DDD.

#include <cstdint>
#include <string_view>

namespace vifusion::discovery {

inline constexpr std::uint16_t kIntelVendorId = 0x8086;
inline constexpr std::uint16_t kCameraProductId = 0x0acb;   ///< DS4: IR, depth, colour (librealsense "ZR300_CX3_PID")
inline constexpr std::uint16_t kAdapterProductId = 0x0ad0;  ///< fisheye + motion module ("ZR300_FISHEYE_PID")

/// A uvcvideo node's sysfs `index` is its registration order within the UVC function's v4l2_device
/// (v4l2-dev.c get_index()); uvcvideo registers each streaming interface's capture node first and its
/// metadata node (V4L2_META_FMT_UVC, kernel ≥ 4.16) right after, so in a function with one streaming
/// interface, as all four of the ZR300's are, the capture node has index 0 and the metadata node index 1.
inline constexpr int kCaptureNodeIndex = 0;

/// The udev rules that hand the ZR300's nodes to groups (mode 0660), as installed from systemd/.
/// Permission errors name the rule file and the group; a test checks these against the file itself.
inline constexpr std::string_view kUdevRulesFile = "99-vifusion.rules";
inline constexpr std::string_view kVideoNodeGroup = "video";  ///< /dev/video* of both USB devices
inline constexpr std::string_view kUsbNodeGroup = "plugdev";  ///< /dev/bus/usb/BBB/DDD of both USB devices

}  // namespace vifusion::discovery
