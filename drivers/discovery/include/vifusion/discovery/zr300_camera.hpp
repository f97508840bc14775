#pragma once
// What discovery found of one ZR300: its two USB devices and the device nodes the drivers open. Built at
// start-up and after a hotplug event, never on the per-frame path, so it holds std::strings.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace vifusion::discovery {

/// The DS4's capture nodes in ascending bInterfaceNumber (librealsense's subdevices 0, 1, 2).
enum class Zr300Stream : std::uint8_t { kInfrared = 0, kDepth = 1, kColour = 2 };
inline constexpr std::size_t kZr300StreamCount = 3;

/// "IR", "depth", "colour": for messages.
std::string_view streamName(Zr300Stream stream);

/// One USB device (not interface) as sysfs and udev describe it.
struct UsbDeviceInfo {
  std::string syspath;  ///< /sys/devices/…/4-2.1: what a person can inspect
  std::string devpath;  ///< the same without "/sys" (/devices/…/4-2.1): what uevents carry
  std::string devnode;  ///< /dev/bus/usb/BBB/DDD, the usbfs node libusb opens
  int busnum = 0;       ///< USB bus number (sysfs busnum, 1…)
  int devnum = 0;       ///< address on that bus (sysfs devnum, 1…127); new at every plug-in
  std::string serial;   ///< sysfs `serial` (iSerialNumber); empty when the device has none
};

/// One /dev/video* node of a UVC function.
struct VideoNodeInfo {
  std::string devnode;        ///< /dev/videoN
  std::string syspath;        ///< /sys/devices/…/4-2.1:1.2/video4linux/videoN
  int interface_number = -1;  ///< bInterfaceNumber of the VideoControl interface the node belongs to
};

/// The adapter board 8086:0ad0 on the camera's hub.
struct Zr300Adapter {
  UsbDeviceInfo usb;                     ///< libusb opens usb.devnode to reach the motion module (interface 2)
  std::optional<VideoNodeInfo> fisheye;  ///< absent when uvcvideo has not bound the fisheye function
};

struct Zr300Camera {
  /// The DS4 (8086:0acb). Its iSerialNumber is the camera's serial: the adapter board has none.
  UsbDeviceInfo camera_usb;
  /// Its video capture nodes (sysfs index 0), ascending bInterfaceNumber. Three on a working camera; none
  /// when uvcvideo is not bound to it.
  std::vector<VideoNodeInfo> capture_nodes;
  /// Its other video nodes (index ≥ 1: the UVC metadata nodes), counted and not used.
  int skipped_video_nodes = 0;
  /// The adapter board on the same internal hub, when present.
  std::optional<Zr300Adapter> adapter;

  const std::string& serial() const { return camera_usb.serial; }
  /// Devpath of the internal hub both USB devices hang under (the camera's parent device).
  std::string_view hubDevpath() const;
  bool hasAllStreams() const { return capture_nodes.size() == kZr300StreamCount; }
  /// Precondition: hasAllStreams().
  const VideoNodeInfo& stream(Zr300Stream which) const;
  /// "ZR300 SN_4071801153", or "ZR300 at /sys/…" for a camera without a serial: for messages.
  std::string label() const;
};

/// Everything one scan of the system found.
struct CameraScan {
  std::vector<Zr300Camera> cameras;  ///< every 8086:0acb, complete or not, by serial then devpath
  /// Adapter boards with no 8086:0acb on their hub: a ZR300 whose DS4 did not enumerate (a bad cable or
  /// port shows this: the adapter comes up, the camera fails), named in the "no camera" error.
  std::vector<UsbDeviceInfo> adapters_without_camera;
};

}  // namespace vifusion::discovery
