#include "vifusion/discovery/hotplug_monitor.hpp"

#include <libudev.h>

#include <cerrno>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <string>

#include "udev_helpers.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/discovery/discovery_error.hpp"
#include "vifusion/discovery/zr300_usb.hpp"

namespace vifusion::discovery {
namespace {

// udev's netlink group: events after udev ran its rules (the kernel's group would announce a node before
// udev has given it its group and mode).
constexpr const char* kUdevEventSource = "udev";

[[noreturn]] void throwMonitorUnavailable(const std::string& what, int error) {
  throw DiscoveryError(DiscoveryProblem::kUdevUnavailable,
                       "libudev hotplug monitor: " + what + ": " + std::strerror(error) +
                           " (without udev's netlink events, e.g. in a container, an unplugged camera is not noticed)");
}

template <std::size_t kCapacity>
void assignOrThrow(FixedString<kCapacity>& field, std::string_view text, const char* what, const std::string& label) {
  if (!field.assign(text)) {
    throw Error("hotplug monitor for " + label + ": " + what + " has " + std::to_string(text.size()) +
                " bytes, more than the " + std::to_string(kCapacity) + " it can hold");
  }
}

}  // namespace

std::string_view actionName(HotplugAction action) { return action == HotplugAction::kAdded ? "added" : "removed"; }

std::string_view partName(Zr300Part part) {
  switch (part) {
    case Zr300Part::kCamera:
      return "camera";
    case Zr300Part::kAdapter:
      return "adapter board";
    case Zr300Part::kCameraVideoNode:
      return "camera video node";
    case Zr300Part::kAdapterVideoNode:
      return "adapter board video node";
  }
  return "unknown part";
}

void HotplugMonitor::UdevRelease::operator()(udev* handle) const { udev_unref(handle); }
void HotplugMonitor::UdevRelease::operator()(udev_monitor* handle) const { udev_monitor_unref(handle); }

HotplugMonitor::HotplugMonitor(const Zr300Camera& target) {
  follow(target);
  udev_.reset(udev_new());
  if (!udev_) throwMonitorUnavailable("udev_new()", errno);
  monitor_.reset(udev_monitor_new_from_netlink(udev_.get(), kUdevEventSource));
  if (!monitor_) throwMonitorUnavailable("cannot open udev's netlink socket", errno);
  // Filters run in the kernel (a socket filter) before a message is even queued for this process.
  if (const int result = udev_monitor_filter_add_match_subsystem_devtype(monitor_.get(), "usb", "usb_device");
      result < 0) {
    throwMonitorUnavailable("cannot filter subsystem usb", -result);
  }
  if (const int result = udev_monitor_filter_add_match_subsystem_devtype(monitor_.get(), "video4linux", nullptr);
      result < 0) {
    throwMonitorUnavailable("cannot filter subsystem video4linux", -result);
  }
  if (const int result = udev_monitor_enable_receiving(monitor_.get()); result < 0) {
    throwMonitorUnavailable("cannot start receiving", -result);
  }
}

void HotplugMonitor::follow(const Zr300Camera& target) {
  const std::string label = target.label();
  assignOrThrow(serial_, target.serial(), "the serial", label);
  assignOrThrow(camera_devpath_, target.camera_usb.devpath, "the camera's devpath", label);
  assignOrThrow(hub_devpath_, target.hubDevpath(), "the hub's devpath", label);
  if (target.adapter) {
    assignOrThrow(adapter_devpath_, target.adapter->usb.devpath, "the adapter board's devpath", label);
  } else {
    adapter_devpath_.clear();
  }
}

int HotplugMonitor::fd() const { return udev_monitor_get_fd(monitor_.get()); }

bool HotplugMonitor::next(HotplugEvent& event) {
  for (int message = 0; message < kMaxMessagesPerNext; ++message) {
    // The socket is non-blocking: with nothing pending libudev returns nullptr and errno EAGAIN.
    errno = 0;
    udev_device* device = udev_monitor_receive_device(monitor_.get());
    if (device == nullptr) {
      const int error = errno;
      if (error == EAGAIN || error == EWOULDBLOCK || error == 0) return false;
      ++counters_.receive_failures;
      noteProblem("uevent not received: %s%s", std::strerror(error),
                  error == ENOBUFS ? " (events were lost: scan again)" : "");
      continue;
    }
    const bool relevant = classify(device, event);
    udev_device_unref(device);
    if (relevant) {
      ++counters_.reported;
      return true;
    }
  }
  return false;
}

bool HotplugMonitor::classify(udev_device* device, HotplugEvent& event) {
  const char* action_text = udev_device_get_action(device);
  const char* subsystem_text = udev_device_get_subsystem(device);
  const char* devpath_text = udev_device_get_devpath(device);
  if (action_text == nullptr || subsystem_text == nullptr || devpath_text == nullptr) {
    ++counters_.malformed;
    noteProblem("uevent without %s", action_text == nullptr      ? "ACTION"
                                     : subsystem_text == nullptr ? "SUBSYSTEM"
                                                                 : "DEVPATH");
    return false;
  }
  const std::string_view action_name(action_text);
  const std::string_view subsystem(subsystem_text);
  const std::string_view devpath(devpath_text);
  if (devpath.size() > kMaxDevpathBytes) {
    ++counters_.malformed;
    noteProblem("uevent %s %s: DEVPATH has %zu bytes, more than %zu", action_text, subsystem_text, devpath.size(),
                kMaxDevpathBytes);
    return false;
  }

  // Only arrivals and departures matter; bind, unbind, change and move do not change what is present.
  std::optional<HotplugAction> action;
  if (action_name == "add") action = HotplugAction::kAdded;
  if (action_name == "remove") action = HotplugAction::kRemoved;

  std::optional<Zr300Part> part;
  if (action && subsystem == "usb") part = usbDevicePart(device, *action, devpath);
  if (action && subsystem == "video4linux") {
    if (detail::isBelow(devpath, camera_devpath_.view())) part = Zr300Part::kCameraVideoNode;
    if (detail::isBelow(devpath, adapter_devpath_.view())) part = Zr300Part::kAdapterVideoNode;
  }
  if (!part) {
    ++counters_.ignored;
    return false;
  }
  event.action = *action;
  event.part = *part;
  event.devpath.assign(devpath);  // fits: checked above
  const char* devnode = udev_device_get_devnode(device);
  if (devnode == nullptr || !event.devnode.assign(devnode)) event.devnode.clear();
  return true;
}

std::optional<Zr300Part> HotplugMonitor::usbDevicePart(udev_device* device, HotplugAction action,
                                                       std::string_view devpath) {
  const char* devtype = udev_device_get_devtype(device);
  if (devtype == nullptr || std::string_view(devtype) != "usb_device") return std::nullopt;
  if (action == HotplugAction::kRemoved) {
    // sysfs is gone: known devpaths are all there is to go by.
    if (devpath == camera_devpath_.view()) return Zr300Part::kCamera;
    if (!adapter_devpath_.empty() && devpath == adapter_devpath_.view()) return Zr300Part::kAdapter;
    return std::nullopt;
  }

  const auto ids = detail::usbIdsOf(device);
  if (!ids || ids->vendor != kIntelVendorId) return std::nullopt;
  const std::string_view hub = detail::parentDevpath(devpath);
  if (ids->product == kCameraProductId) {
    const bool is_target =
        serial_.empty() ? !hub.empty() && hub == hub_devpath_.view() : detail::usbSerialOf(device) == serial_.view();
    if (!is_target) return std::nullopt;
    // Plugged in again, perhaps into another port: its devices now live under this hub.
    camera_devpath_.assign(devpath);
    hub_devpath_.assign(hub);
    return Zr300Part::kCamera;
  }
  if (ids->product == kAdapterProductId && !hub.empty() && hub == hub_devpath_.view()) {
    adapter_devpath_.assign(devpath);
    return Zr300Part::kAdapter;
  }
  return std::nullopt;
}

void HotplugMonitor::noteProblem(const char* format, ...) {
  char text[kMaxProblemBytes + 1];
  va_list arguments;
  va_start(arguments, format);
  std::vsnprintf(text, sizeof(text), format, arguments);
  va_end(arguments);
  last_problem_.assign(text);
}

}  // namespace vifusion::discovery
