#include "vifusion/discovery/select_camera.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

#include "vifusion/discovery/discovery_error.hpp"
#include "vifusion/discovery/find_cameras.hpp"
#include "vifusion/discovery/zr300_usb.hpp"

namespace vifusion::discovery {
namespace {

/// "8086:0acb": USB ids as lsusb and sysfs print them.
std::string usbIdText(std::uint16_t product) {
  char text[sizeof("ffff:ffff")];
  std::snprintf(text, sizeof(text), "%04x:%04x", kIntelVendorId, product);
  return text;
}

std::string cameraList(const CameraScan& scan) {
  std::string list;
  for (const Zr300Camera& camera : scan.cameras) {
    if (!list.empty()) list += ", ";
    list += camera.serial().empty() ? "(no serial) at " + camera.camera_usb.syspath : camera.serial();
  }
  return list;
}

std::string noCameraMessage(const CameraScan& scan, const Zr300SourceSpec& spec) {
  std::string message = "no ZR300 (" + usbIdText(kCameraProductId) + ") on any USB bus";
  if (!spec.serial.empty()) message += " (looking for serial '" + spec.serial + "')";
  if (!scan.adapters_without_camera.empty()) {
    message += "; an adapter board " + usbIdText(kAdapterProductId) + " is there (" +
               scan.adapters_without_camera.front().syspath +
               ") but its camera did not enumerate: check the cable and use a USB 3 port (dmesg shows the USB "
               "errors)";
  }
  return message;
}

/// What the drivers will do with a node, for messages and for the udev rule that governs it.
struct NodeUse {
  std::string what;        ///< "ZR300 SN_… depth node"
  std::string_view group;  ///< the group 99-vifusion.rules gives such nodes
  std::string_view kind;   ///< "video4linux", "USB device"
};

/// access(2), not faccessat(AT_EACCESS): vifusiond is not set-id, so real and effective ids agree, and
/// access() is what umockdev's preload library redirects into a test bed.
void checkNodeAccess(const std::string& devnode, const NodeUse& use) {
  if (devnode.empty()) {
    throw DiscoveryError(DiscoveryProblem::kNodeMissing, use.what + " has no device node: udev gave it no DEVNAME");
  }
  if (::access(devnode.c_str(), R_OK | W_OK) == 0) return;
  const int error = errno;
  if (error == ENOENT) {
    throw DiscoveryError(DiscoveryProblem::kNodeMissing,
                         "sysfs lists " + devnode + " (" + use.what +
                             ") but it does not exist: udev did not create it (is systemd-udevd running? a container "
                             "needs the host's /dev)");
  }
  if (error == EACCES || error == EPERM) {
    const std::string group(use.group);
    throw DiscoveryError(
        DiscoveryProblem::kPermissionDenied,
        "permission denied on " + devnode + " (" + use.what + "): the udev rules " + std::string(kUdevRulesFile) +
            " (systemd/ in the source tree, /lib/udev/rules.d/ once "
            "installed) give the ZR300's " +
            std::string(use.kind) + " nodes to group '" + group + "' with mode 0660: run as a member of '" + group +
            "' (vifusiond.service: SupplementaryGroups=) and, after installing the rules, run "
            "'udevadm control --reload && udevadm trigger'");
  }
  throw DiscoveryError(DiscoveryProblem::kNodeInaccessible,
                       "cannot check access to " + devnode + " (" + use.what + "): " + std::strerror(error));
}

std::string captureNodeList(const Zr300Camera& camera) {
  std::string list;
  for (const VideoNodeInfo& node : camera.capture_nodes) {
    if (!list.empty()) list += ", ";
    list += node.devnode + " at interface " + std::to_string(node.interface_number);
  }
  return list;
}

}  // namespace

const Zr300Camera& selectCamera(const CameraScan& scan, const Zr300SourceSpec& spec) {
  if (scan.cameras.empty()) throw DiscoveryError(DiscoveryProblem::kNoCamera, noCameraMessage(scan, spec));
  if (spec.serial.empty()) {
    if (scan.cameras.size() == 1) return scan.cameras.front();
    throw DiscoveryError(DiscoveryProblem::kAmbiguous, std::to_string(scan.cameras.size()) +
                                                           " ZR300 cameras found (serials " + cameraList(scan) +
                                                           "): choose one with the source zr300:SERIAL");
  }
  for (const Zr300Camera& camera : scan.cameras) {
    if (serialMatches(spec.serial, camera.serial())) return camera;
  }
  throw DiscoveryError(DiscoveryProblem::kSerialNotFound,
                       "no ZR300 with serial '" + spec.serial + "'; found " + cameraList(scan));
}

void checkCamera(const Zr300Camera& camera, const CameraCheckOptions& options) {
  const std::string found =
      "found " + usbIdText(kCameraProductId) + " (" + camera.label() + ", " + camera.camera_usb.syspath + ")";
  if (camera.capture_nodes.empty() && camera.skipped_video_nodes == 0) {
    throw DiscoveryError(DiscoveryProblem::kUvcNotBound,
                         found +
                             " but no video4linux nodes under it: the uvcvideo driver is not bound to it "
                             "('modprobe uvcvideo'; dmesg shows why binding failed)");
  }
  if (!camera.hasAllStreams()) {
    throw DiscoveryError(DiscoveryProblem::kMissingStreams,
                         found + " with " + std::to_string(camera.capture_nodes.size()) + " video capture nodes (" +
                             (camera.capture_nodes.empty() ? std::string("none") : captureNodeList(camera)) +
                             "), expected " + std::to_string(kZr300StreamCount) +
                             ": IR, depth and colour in bInterfaceNumber order");
  }
  if (options.require_adapter && !camera.adapter) {
    throw DiscoveryError(DiscoveryProblem::kNoAdapter,
                         found + " but no adapter board " + usbIdText(kAdapterProductId) + " on its hub (/sys" +
                             std::string(camera.hubDevpath()) +
                             "): the IMU (motion module) and the fisheye camera are unavailable");
  }
  if (!options.check_access) return;
  for (std::size_t index = 0; index < kZr300StreamCount; ++index) {
    const auto stream = static_cast<Zr300Stream>(index);
    checkNodeAccess(camera.stream(stream).devnode,
                    {camera.label() + " " + std::string(streamName(stream)) + " node", kVideoNodeGroup, "video4linux"});
  }
  // The fisheye node is opened only with the IMU: its strobe puts frame events on the IMU's clock.
  if (!options.require_adapter) return;
  checkNodeAccess(camera.adapter->usb.devnode,
                  {camera.label() + " adapter board (IMU) USB node", kUsbNodeGroup, "USB device"});
  if (camera.adapter->fisheye) {
    checkNodeAccess(camera.adapter->fisheye->devnode,
                    {camera.label() + " fisheye node", kVideoNodeGroup, "video4linux"});
  }
}

Zr300Camera findCamera(const Zr300SourceSpec& spec, const CameraCheckOptions& options) {
  const CameraScan scan = findCameras();
  const Zr300Camera& camera = selectCamera(scan, spec);
  checkCamera(camera, options);
  return camera;
}

}  // namespace vifusion::discovery
