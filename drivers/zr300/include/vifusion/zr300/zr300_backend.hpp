#pragma once
// How the live source reaches the hardware: discovery, the V4L2 syscalls, the motion module's USB link and
// hotplug events, behind one interface. The system backend (system_backend.hpp) uses libudev, the real
// system calls and libusb; the tests put a scripted camera behind the same calls (an in-memory V4L2 device
// and a scripted motion module), so everything above this line — the source, `vifusion run --source zr300`
// and the service — runs its real code paths without a camera.

#include <cstdint>
#include <memory>

#include "vifusion/discovery/select_camera.hpp"
#include "vifusion/discovery/source_spec.hpp"
#include "vifusion/discovery/zr300_camera.hpp"
#include "vifusion/usb_imu/usb_link.hpp"
#include "vifusion/v4l2/device_io.hpp"

namespace vifusion::zr300 {

class Zr300Backend {
 public:
  virtual ~Zr300Backend() = default;

  /// The camera `spec` names, checked (discovery::findCamera).
  /// @throws discovery::DiscoveryError naming what is missing.
  virtual discovery::Zr300Camera findCamera(const discovery::Zr300SourceSpec& spec,
                                            const discovery::CameraCheckOptions& options) = 0;
  /// The syscalls every V4L2 node of the camera is reached through; lives as long as the backend.
  virtual v4l2::DeviceIo& deviceIo() = 0;
  /// A link to the motion module on `camera`'s adapter board (precondition: camera.adapter).
  virtual std::unique_ptr<usb_imu::UsbLink> motionLink(const discovery::Zr300Camera& camera,
                                                       std::size_t transfers_in_flight) = 0;
  /// Starts following `camera` through hotplug events (after each successful open).
  virtual void follow(const discovery::Zr300Camera& camera) = 0;
  /// Waits up to `timeout_ns` for a hotplug event about the followed camera; true when one came. Returning
  /// false early is allowed (the caller retries on its backoff schedule anyway).
  virtual bool waitForHotplug(std::int64_t timeout_ns) = 0;
};

}  // namespace vifusion::zr300
