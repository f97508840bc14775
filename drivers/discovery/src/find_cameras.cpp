#include "vifusion/discovery/find_cameras.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <tuple>

#include "udev_helpers.hpp"
#include "vifusion/discovery/discovery_error.hpp"
#include "vifusion/discovery/zr300_usb.hpp"

namespace vifusion::discovery {
namespace {

using detail::UdevDeviceHandle;
using detail::UdevEnumerateHandle;
using detail::UdevHandle;

constexpr std::uint32_t kMaxInterfaceNumber = 0xff;  // bInterfaceNumber is one byte

std::string orEmpty(const char* text) { return text == nullptr ? std::string() : std::string(text); }

[[noreturn]] void throwUdevUnavailable(const std::string& what, int error) {
  throw DiscoveryError(DiscoveryProblem::kUdevUnavailable, "libudev: " + what + ": " + std::strerror(error));
}

/// Where usbfs puts a device's node when udev is not there to tell (DEVNAME): /dev/bus/usb/BBB/DDD.
std::string usbfsDevnode(int busnum, int devnum) {
  char path[sizeof("/dev/bus/usb/-2147483648/-2147483648")];  // any int fits; real ones have three digits
  std::snprintf(path, sizeof(path), "/dev/bus/usb/%03d/%03d", busnum, devnum);
  return path;
}

UsbDeviceInfo usbDeviceInfo(udev_device* device) {
  UsbDeviceInfo info;
  info.syspath = orEmpty(udev_device_get_syspath(device));
  info.devpath = orEmpty(udev_device_get_devpath(device));
  info.busnum = detail::parseDecimal(detail::sysattrOf(device, "busnum")).value_or(0);
  info.devnum = detail::parseDecimal(detail::sysattrOf(device, "devnum")).value_or(0);
  info.devnode = orEmpty(udev_device_get_devnode(device));
  if (info.devnode.empty() && info.busnum > 0 && info.devnum > 0) info.devnode = usbfsDevnode(info.busnum, info.devnum);
  info.serial = std::string(detail::usbSerialOf(device));
  return info;
}

/// Calls visit(udev_device*) for every device of `subsystem` present now.
template <class Visit>
void forEachDevice(udev* context, const char* subsystem, Visit&& visit) {
  UdevEnumerateHandle enumerate(udev_enumerate_new(context));
  if (!enumerate) throwUdevUnavailable("udev_enumerate_new()", errno);
  const std::string what = std::string("cannot enumerate subsystem ") + subsystem;
  if (const int result = udev_enumerate_add_match_subsystem(enumerate.get(), subsystem); result < 0) {
    throwUdevUnavailable(what, -result);
  }
  if (const int result = udev_enumerate_scan_devices(enumerate.get()); result < 0) throwUdevUnavailable(what, -result);
  udev_list_entry* entry = nullptr;
  udev_list_entry_foreach(entry, udev_enumerate_get_list_entry(enumerate.get())) {
    // A device that left between listing and reading is simply not there any more.
    UdevDeviceHandle device(udev_device_new_from_syspath(context, udev_list_entry_get_name(entry)));
    if (device) visit(device.get());
  }
}

/// One USB device of a ZR300 with the video nodes found under it.
struct UsbDeviceNodes {
  UsbDeviceInfo usb;
  std::vector<VideoNodeInfo> capture_nodes;
  int skipped_video_nodes = 0;
};

bool byInterfaceThenDevnode(const VideoNodeInfo& a, const VideoNodeInfo& b) {
  return std::tie(a.interface_number, a.devnode) < std::tie(b.interface_number, b.devnode);
}

/// Adds a video4linux node to the ZR300 USB device it belongs to, if any.
void addVideoNode(udev_device* node, std::vector<UsbDeviceNodes>& devices) {
  // Parents are owned by (and freed with) the child device.
  udev_device* usb_device = udev_device_get_parent_with_subsystem_devtype(node, "usb", "usb_device");
  if (usb_device == nullptr) return;  // not a USB video device (a CSI camera, vivid, …)
  const std::string usb_devpath = orEmpty(udev_device_get_devpath(usb_device));
  const auto owner = std::find_if(devices.begin(), devices.end(),
                                  [&](const UsbDeviceNodes& device) { return device.usb.devpath == usb_devpath; });
  if (owner == devices.end()) return;

  if (detail::parseDecimal(detail::sysattrOf(node, "index")) != kCaptureNodeIndex) {
    ++owner->skipped_video_nodes;
    return;
  }
  VideoNodeInfo info;
  info.devnode = orEmpty(udev_device_get_devnode(node));
  info.syspath = orEmpty(udev_device_get_syspath(node));
  if (udev_device* interface = udev_device_get_parent_with_subsystem_devtype(node, "usb", "usb_interface")) {
    // sysfs writes bInterfaceNumber as two hex digits ("04").
    const auto number = detail::parseHex(detail::sysattrOf(interface, "bInterfaceNumber"), kMaxInterfaceNumber);
    info.interface_number = number ? static_cast<int>(*number) : -1;
  }
  owner->capture_nodes.push_back(std::move(info));
}

}  // namespace

CameraScan findCameras() {
  UdevHandle context(udev_new());
  if (!context) throwUdevUnavailable("udev_new()", errno);

  std::vector<UsbDeviceNodes> cameras;
  std::vector<UsbDeviceNodes> adapters;
  forEachDevice(context.get(), "usb", [&](udev_device* device) {
    // The usb subsystem also lists every interface; only devices carry idVendor/idProduct.
    const char* devtype = udev_device_get_devtype(device);
    if (devtype == nullptr || std::string_view(devtype) != "usb_device") return;
    const auto ids = detail::usbIdsOf(device);
    if (!ids || ids->vendor != kIntelVendorId) return;
    if (ids->product == kCameraProductId) cameras.push_back({usbDeviceInfo(device), {}, 0});
    if (ids->product == kAdapterProductId) adapters.push_back({usbDeviceInfo(device), {}, 0});
  });
  forEachDevice(context.get(), "video4linux", [&](udev_device* node) {
    addVideoNode(node, cameras);
    addVideoNode(node, adapters);
  });

  CameraScan scan;
  for (UsbDeviceNodes& found : cameras) {
    Zr300Camera camera;
    camera.camera_usb = std::move(found.usb);
    camera.capture_nodes = std::move(found.capture_nodes);
    std::sort(camera.capture_nodes.begin(), camera.capture_nodes.end(), byInterfaceThenDevnode);
    camera.skipped_video_nodes = found.skipped_video_nodes;
    scan.cameras.push_back(std::move(camera));
  }
  for (UsbDeviceNodes& found : adapters) {
    const std::string_view hub = detail::parentDevpath(found.usb.devpath);
    const auto camera = std::find_if(scan.cameras.begin(), scan.cameras.end(), [&](const Zr300Camera& candidate) {
      return !candidate.adapter && !hub.empty() && candidate.hubDevpath() == hub;
    });
    if (camera == scan.cameras.end()) {
      scan.adapters_without_camera.push_back(std::move(found.usb));
      continue;
    }
    Zr300Adapter adapter;
    adapter.usb = std::move(found.usb);
    // The fisheye function is the adapter's only UVC function; take the lowest interface if there were more.
    const auto fisheye =
        std::min_element(found.capture_nodes.begin(), found.capture_nodes.end(), byInterfaceThenDevnode);
    if (fisheye != found.capture_nodes.end()) adapter.fisheye = std::move(*fisheye);
    camera->adapter = std::move(adapter);
  }
  std::sort(scan.cameras.begin(), scan.cameras.end(), [](const Zr300Camera& a, const Zr300Camera& b) {
    return std::tie(a.camera_usb.serial, a.camera_usb.devpath) < std::tie(b.camera_usb.serial, b.camera_usb.devpath);
  });
  return scan;
}

}  // namespace vifusion::discovery
