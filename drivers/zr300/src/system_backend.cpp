#include "vifusion/zr300/system_backend.hpp"

#include <poll.h>

#include <optional>

#include "vifusion/core/time.hpp"
#include "vifusion/discovery/hotplug_monitor.hpp"
#include "vifusion/usb_imu/libusb_link.hpp"

namespace vifusion::zr300 {
namespace {

class SystemBackend final : public Zr300Backend {
 public:
  discovery::Zr300Camera findCamera(const discovery::Zr300SourceSpec& spec,
                                    const discovery::CameraCheckOptions& options) override {
    return discovery::findCamera(spec, options);
  }

  v4l2::DeviceIo& deviceIo() override { return io_; }

  std::unique_ptr<usb_imu::UsbLink> motionLink(const discovery::Zr300Camera& camera,
                                               std::size_t transfers_in_flight) override {
    return std::make_unique<usb_imu::LibusbLink>(camera.adapter->usb.devnode, transfers_in_flight);
  }

  void follow(const discovery::Zr300Camera& camera) override {
    if (monitor_) {
      monitor_->follow(camera);
    } else {
      monitor_.emplace(camera);
    }
  }

  bool waitForHotplug(std::int64_t timeout_ns) override {
    if (!monitor_) return false;
    discovery::HotplugEvent event;
    if (monitor_->next(event)) return true;
    pollfd fd{monitor_->fd(), POLLIN, 0};
    const int timeout_ms = static_cast<int>((timeout_ns + kNsPerMillisecond - 1) / kNsPerMillisecond);
    if (::poll(&fd, 1, timeout_ms) <= 0) return false;
    return monitor_->next(event);
  }

 private:
  v4l2::SystemDeviceIo io_;
  std::optional<discovery::HotplugMonitor> monitor_;
};

}  // namespace

std::unique_ptr<Zr300Backend> makeSystemBackend() { return std::make_unique<SystemBackend>(); }

}  // namespace vifusion::zr300
