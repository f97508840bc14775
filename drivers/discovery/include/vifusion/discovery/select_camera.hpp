#pragma once
// From a source spec and a scan to the one camera to open, or a DiscoveryError that says what is missing:
//
//   findCamera(spec)  =  checkCamera(selectCamera(findCameras(), spec))
//
// Selection names the camera (no camera, unknown serial, several without a serial); the check names what
// that camera lacks, in the order a person would fix it: uvcvideo not bound → capture nodes missing →
// adapter board missing → a device node that udev did not create → a node this process may not open.

#include "vifusion/discovery/source_spec.hpp"
#include "vifusion/discovery/zr300_camera.hpp"

namespace vifusion::discovery {

struct CameraCheckOptions {
  /// The motion module (IMU) is on the adapter board: modes rgbdi and gyro need it, rgbd does not.
  bool require_adapter = true;
  /// Check with access(2) that this process may read and write every node the drivers open: the three
  /// capture nodes and, when the adapter is required, its usbfs node and its fisheye node (if present).
  /// Off only for tools that merely list cameras.
  bool check_access = true;
};

/// The camera `spec` names among `scan.cameras`.
/// @throws DiscoveryError kNoCamera, kSerialNotFound or kAmbiguous; the message lists the serials found.
const Zr300Camera& selectCamera(const CameraScan& scan, const Zr300SourceSpec& spec);

/// @throws DiscoveryError kUvcNotBound, kMissingStreams, kNoAdapter, kNodeMissing, kPermissionDenied or
///         kNodeInaccessible for the first thing `camera` lacks; the message names the camera and the node.
void checkCamera(const Zr300Camera& camera, const CameraCheckOptions& options = {});

/// Scans, selects and checks: the camera the live source opens.
Zr300Camera findCamera(const Zr300SourceSpec& spec, const CameraCheckOptions& options = {});

}  // namespace vifusion::discovery
