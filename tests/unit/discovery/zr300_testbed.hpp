#pragma once
// ZR300s in a umockdev test bed: the sysfs tree, uevent variables, udev properties and /dev nodes a real
// one has, built from the documented topology (sensors.md §1.1; dmesg of real units: internal hub at B-P,
// DS4 8086:0acb at B-P.1 with VideoControl interfaces 0, 2, 4, adapter 8086:0ad0 "CX3-UVC" at B-P.2 with its
// VideoControl interface 0 and the motion module's vendor interface 2, no serial).
//
// The test binary runs under umockdev-wrapper (LD_PRELOAD of libumockdev-preload), which diverts libudev's
// /sys, /dev and netlink access into the test bed, so the code under test is the real libudev code.

#include <umockdev.h>

#include <array>
#include <functional>
#include <string>
#include <vector>

namespace vifusion::discovery::test {

/// What to build; the defaults are a complete camera on bus 4, hub port 2.
struct FakeZr300 {
  int bus = 4;
  int hub_port = 2;
  std::string serial = "SN_4071801153";  ///< empty: the DS4 has no serial attribute
  int bound_camera_functions = 3;        ///< UVC functions of the DS4 with video nodes (0: uvcvideo not bound)
  bool metadata_nodes = true;            ///< kernel ≥ 4.16 adds a metadata node per streaming interface
  bool camera_present = true;            ///< false: only the hub and the adapter enumerated
  bool adapter = true;
  bool adapter_video_nodes = true;
};

/// Where the built devices are: sysfs paths (/sys/…), as discovery reports them.
struct FakeZr300Paths {
  std::string hub;
  std::string camera;                            ///< empty when !camera_present
  std::string adapter;                           ///< empty when !adapter
  std::vector<std::string> interfaces;           ///< every USB interface of both devices
  std::vector<std::string> camera_video_nodes;   ///< capture and metadata nodes
  std::vector<std::string> adapter_video_nodes;  ///< fisheye capture and metadata node
  /// /dev nodes of the DS4's capture nodes in IR, depth, colour order (empty when not bound).
  std::array<std::string, 3> stream_devnodes;
  std::string fisheye_devnode;
  std::string camera_usb_devnode;
  std::string adapter_usb_devnode;
};

class Zr300Testbed {
 public:
  Zr300Testbed();
  ~Zr300Testbed();
  Zr300Testbed(const Zr300Testbed&) = delete;
  Zr300Testbed& operator=(const Zr300Testbed&) = delete;

  /// Builds the devices, parents first; under the preload library umockdev announces each with an "add"
  /// uevent as it is created, as the kernel does when the camera is plugged in.
  FakeZr300Paths add(const FakeZr300& device);
  /// A USB device that is not a ZR300 (another vendor's webcam, a newer RealSense) with one video node.
  std::string addOtherUsbCamera(int bus, int hub_port, const char* vendor_id, const char* product_id);

  /// Unplugging: "remove" uevents children first, then the devices leave sysfs.
  void unplug(const FakeZr300Paths& paths);

  void uevent(const std::string& syspath, const char* action);
  /// Adds devices described in umockdev's record format ("P: /devices/…", "E: …", "A: …" lines).
  void addFromString(const std::string& description);
  /// Called after every uevent the test bed sends. umockdev's event socket is a Unix datagram socket that
  /// queues only net.unix.max_dgram_qlen (10) messages, and its sender aborts when the queue is full, so
  /// a hotplug test reads its monitor here, as the service's thread would as events arrive.
  void setEventListener(std::function<void()> listener) { event_listener_ = std::move(listener); }
  /// The test bed's directory, whose dev/ holds the fake /dev nodes.
  std::string rootDir() const;
  UMockdevTestbed* raw() { return testbed_; }

 private:
  std::string addVideoNode(const std::string& interface_devpath, int index, bool capture);

  UMockdevTestbed* testbed_ = nullptr;
  std::function<void()> event_listener_;
  int next_video_number_ = 0;
  int next_usb_devnum_ = 8;
};

/// Whether libumockdev-preload is loaded, i.e. the binary runs under umockdev-wrapper.
bool umockdevPreloaded();

}  // namespace vifusion::discovery::test
