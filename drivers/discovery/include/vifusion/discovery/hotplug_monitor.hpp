#pragma once
// Follows one ZR300 through udev's hotplug events, so that the service can report the camera absent when
// it is unplugged and open it again when it comes back.
//
// The monitor listens on udev's netlink socket (events after udev applied its rules, so a node that is
// announced already has its group and mode) for the subsystems usb (USB devices only, not interfaces) and
// video4linux. It reports an event when it concerns the target camera:
//   - the 8086:0acb with the target's serial (or, for a camera without a serial, the one on the target's
//     hub) appearing, or the target's 8086:0acb disappearing;
//   - the 8086:0ad0 on the target's hub appearing or disappearing (the adapter board has no serial: it is
//     known by its hub);
//   - a video node of either appearing or disappearing.
// On removal sysfs is already gone, so removals are matched by devpath: the monitor remembers the devpaths
// of the target's devices, from discovery and from every matching "add" (a camera re-plugged into another
// port gets new devpaths). Everything else is counted as ignored.
//
// A reported "add" means: try to open the camera again (findCamera with the camera's serial, with a backoff:
// uvcvideo binds the video nodes after the USB device, one by one). A reported "remove": the camera is gone.
// When counters().receive_failures grows, events were lost (the socket's buffer overflowed): scan again.
//
// next() never blocks and allocates nothing of its own (fixed buffers); libudev allocates and frees each
// event's udev_device internally. Not thread-safe: one thread owns the monitor.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>

#include "vifusion/discovery/fixed_string.hpp"
#include "vifusion/discovery/zr300_camera.hpp"

struct udev;
struct udev_monitor;
struct udev_device;

namespace vifusion::discovery {

/// Sysfs devpaths of USB and video devices are far shorter (~100 bytes); longer ones are counted malformed.
inline constexpr std::size_t kMaxDevpathBytes = 511;
/// "/dev/video12", "/dev/bus/usb/004/009".
inline constexpr std::size_t kMaxDevnodeBytes = 127;
/// A USB serial of 126 UTF-16 code units, each up to 3 bytes of UTF-8.
inline constexpr std::size_t kMaxSerialBytes = 378;
inline constexpr std::size_t kMaxProblemBytes = 767;
/// next() reads at most this many messages per call, so that a flood of unrelated events (another
/// device's hundreds of nodes) cannot hold the calling thread; the fd stays readable for the next call.
inline constexpr int kMaxMessagesPerNext = 64;

enum class HotplugAction : std::uint8_t { kAdded, kRemoved };
enum class Zr300Part : std::uint8_t {
  kCamera,            ///< the 8086:0acb USB device
  kAdapter,           ///< the 8086:0ad0 USB device
  kCameraVideoNode,   ///< a /dev/video* of the camera (capture or metadata)
  kAdapterVideoNode,  ///< a /dev/video* of the adapter board (fisheye capture or metadata)
};
std::string_view actionName(HotplugAction action);  ///< "added", "removed"
std::string_view partName(Zr300Part part);          ///< "camera 8086:0acb", "adapter 8086:0ad0", …

struct HotplugEvent {
  HotplugAction action = HotplugAction::kAdded;
  Zr300Part part = Zr300Part::kCamera;
  FixedString<kMaxDevpathBytes> devpath;  ///< /devices/…, as the uevent carries it
  FixedString<kMaxDevnodeBytes> devnode;  ///< /dev/…, empty when the device has none
};

struct HotplugCounters {
  std::uint64_t reported = 0;          ///< events next() returned
  std::uint64_t ignored = 0;           ///< other devices, other actions (bind, change, …)
  std::uint64_t malformed = 0;         ///< events without action, subsystem or devpath, or too long a field
  std::uint64_t receive_failures = 0;  ///< messages libudev could not receive (lost events among them)
};

class HotplugMonitor {
 public:
  /// Listens from now on and follows `target` (from findCamera): its serial, or, without one, its hub.
  /// @throws DiscoveryError(kUdevUnavailable) when the udev monitor cannot be set up; vifusion::Error as
  ///         follow() does.
  explicit HotplugMonitor(const Zr300Camera& target);

  /// Follows `target` from now on, with the devpaths a fresh scan found: call it after re-opening the
  /// camera, so that a device whose "add" arrived before its hub was known is followed too.
  /// @throws vifusion::Error when the target's serial or devpaths do not fit the fixed buffers.
  void follow(const Zr300Camera& target);

  /// Readable (POLLIN) when events are pending; poll it with the driver's other fds.
  int fd() const;
  /// Reads pending events until one concerns the target and writes it to `event`. Returns false when none
  /// is pending (then `event` is unchanged); never blocks.
  bool next(HotplugEvent& event);

  const HotplugCounters& counters() const { return counters_; }
  /// The most recent malformed event or receive failure, naming the field or the errno; empty if none.
  std::string_view lastProblem() const { return last_problem_.view(); }

 private:
  struct UdevRelease {
    void operator()(udev* handle) const;
    void operator()(udev_monitor* handle) const;
  };

  /// Whether `device` concerns the target; fills `event` (only then) and learns devpaths.
  bool classify(udev_device* device, HotplugEvent& event);
  /// Which part of the target a usb_device event is about, learning the devpaths of matching "add"s.
  std::optional<Zr300Part> usbDevicePart(udev_device* device, HotplugAction action, std::string_view devpath);
  void noteProblem(const char* format, ...) __attribute__((format(printf, 2, 3)));

  std::unique_ptr<udev, UdevRelease> udev_;
  std::unique_ptr<udev_monitor, UdevRelease> monitor_;  // after udev_: released first
  FixedString<kMaxSerialBytes> serial_;                 ///< the target's USB serial; empty: matched by hub
  FixedString<kMaxDevpathBytes> hub_devpath_;           ///< the internal hub the target was last seen under
  FixedString<kMaxDevpathBytes> camera_devpath_;        ///< the target's 8086:0acb
  FixedString<kMaxDevpathBytes> adapter_devpath_;       ///< the 8086:0ad0 on its hub; empty until seen
  HotplugCounters counters_;
  FixedString<kMaxProblemBytes> last_problem_;
};

}  // namespace vifusion::discovery
