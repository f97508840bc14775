// HotplugMonitor against uevents that umockdev sends for a faked ZR300 being unplugged and plugged in.

#include <gtest/gtest.h>
#include <poll.h>

#include <array>
#include <chrono>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "discovery_fixture.hpp"
#include "vifusion/discovery/find_cameras.hpp"
#include "vifusion/discovery/hotplug_monitor.hpp"
#include "vifusion/discovery/select_camera.hpp"
#include "vifusion/test/counting_allocations.hpp"

namespace vifusion::discovery::test {
namespace {

struct Seen {
  HotplugAction action;
  Zr300Part part;
  std::string devpath;
  std::string devnode;
};

/// Watches one camera and reads the monitor after every uevent, as the service's thread would.
class HotplugMonitorTest : public DiscoveryTest {
 protected:
  void watch(const Zr300Camera& camera) {
    monitor_.emplace(camera);
    testbed().setEventListener([this] { readPending(); });
  }
  HotplugMonitor& monitor() { return *monitor_; }
  /// What the monitor reported since the last call.
  std::vector<Seen> takeSeen() {
    readPending();
    return std::exchange(seen_, {});
  }

 private:
  void readPending() {
    HotplugEvent event;
    while (monitor_->next(event)) {
      seen_.push_back({event.action, event.part, std::string(event.devpath.view()), std::string(event.devnode.view())});
    }
  }

  std::optional<HotplugMonitor> monitor_;
  std::vector<Seen> seen_;
};

std::string devpathOf(const std::string& syspath) { return syspath.substr(std::string("/sys").size()); }

/// The events one camera's unplugging must produce, in the kernel's order (children first).
std::vector<Seen> expectedRemoval(const FakeZr300Paths& paths) {
  std::vector<Seen> expected;
  auto videoNodes = [&](const std::vector<std::string>& nodes, Zr300Part part) {
    for (const std::string& node : nodes) {
      expected.push_back({HotplugAction::kRemoved, part, devpathOf(node), "/dev/" + node.substr(node.rfind('/') + 1)});
    }
  };
  videoNodes(paths.camera_video_nodes, Zr300Part::kCameraVideoNode);
  expected.push_back({HotplugAction::kRemoved, Zr300Part::kCamera, devpathOf(paths.camera), paths.camera_usb_devnode});
  videoNodes(paths.adapter_video_nodes, Zr300Part::kAdapterVideoNode);
  expected.push_back(
      {HotplugAction::kRemoved, Zr300Part::kAdapter, devpathOf(paths.adapter), paths.adapter_usb_devnode});
  return expected;
}

void expectSame(const std::vector<Seen>& seen, const std::vector<Seen>& expected) {
  ASSERT_EQ(seen.size(), expected.size());
  for (std::size_t i = 0; i < seen.size(); ++i) {
    EXPECT_EQ(actionName(seen[i].action), actionName(expected[i].action)) << "event " << i;
    EXPECT_EQ(partName(seen[i].part), partName(expected[i].part)) << "event " << i;
    EXPECT_EQ(seen[i].devpath, expected[i].devpath) << "event " << i;
    EXPECT_EQ(seen[i].devnode, expected[i].devnode) << "event " << i;
  }
}

FakeZr300 elsewhere() {
  FakeZr300 moved;
  moved.bus = 3;
  moved.hub_port = 1;
  return moved;
}

TEST_F(HotplugMonitorTest, UnplugReportsEveryPartOfTheCameraGone) {
  const FakeZr300Paths paths = testbed().add({});
  watch(findCamera({}));
  testbed().unplug(paths);
  expectSame(takeSeen(), expectedRemoval(paths));
  EXPECT_EQ(monitor().counters().reported, 10u);  // 6 + 2 video nodes, 2 USB devices
  EXPECT_EQ(monitor().counters().ignored, 1u);    // the hub (USB interfaces never pass the socket filter)
  EXPECT_EQ(monitor().counters().malformed, 0u);
  EXPECT_EQ(monitor().counters().receive_failures, 0u);
}

TEST_F(HotplugMonitorTest, RemovalsAreMatchedAfterSysfsIsGone) {
  const FakeZr300Paths paths = testbed().add({});
  HotplugMonitor unread(findCamera({}));
  // The events wait in the socket while the devices leave sysfs, as when the service is busy.
  testbed().uevent(paths.camera_video_nodes[4], "remove");
  testbed().uevent(paths.camera, "remove");
  testbed().uevent(paths.adapter, "remove");
  umockdev_testbed_remove_device(testbed().raw(), paths.hub.c_str());
  HotplugEvent event;
  ASSERT_TRUE(unread.next(event));
  EXPECT_EQ(partName(event.part), partName(Zr300Part::kCameraVideoNode));
  EXPECT_EQ(event.devpath.view(), devpathOf(paths.camera_video_nodes[4]));
  EXPECT_EQ(event.devnode.view(), paths.stream_devnodes[1]);
  ASSERT_TRUE(unread.next(event));
  EXPECT_EQ(partName(event.part), partName(Zr300Part::kCamera));
  ASSERT_TRUE(unread.next(event));
  EXPECT_EQ(partName(event.part), partName(Zr300Part::kAdapter));
  EXPECT_FALSE(unread.next(event));
}

TEST_F(HotplugMonitorTest, PluggedBackIntoAnotherPortTheCameraIsFollowed) {
  const FakeZr300Paths before = testbed().add({});
  const Zr300Camera camera = findCamera({});
  watch(camera);
  testbed().unplug(before);
  ASSERT_EQ(takeSeen().size(), 10u);

  const FakeZr300Paths after = testbed().add(elsewhere());
  const std::vector<Seen> added = takeSeen();
  ASSERT_EQ(added.size(), 10u);
  EXPECT_EQ(partName(added[0].part), partName(Zr300Part::kCamera));
  EXPECT_EQ(actionName(added[0].action), "added");
  EXPECT_EQ(added[0].devpath, devpathOf(after.camera));
  EXPECT_EQ(added[0].devnode, after.camera_usb_devnode);
  for (std::size_t i = 1; i <= 6; ++i) {
    EXPECT_EQ(partName(added[i].part), partName(Zr300Part::kCameraVideoNode));
    EXPECT_EQ(added[i].devpath, devpathOf(after.camera_video_nodes[i - 1]));
  }
  EXPECT_EQ(partName(added[7].part), partName(Zr300Part::kAdapter));  // known by the camera's new hub
  EXPECT_EQ(added[7].devpath, devpathOf(after.adapter));
  EXPECT_EQ(partName(added[8].part), partName(Zr300Part::kAdapterVideoNode));
  EXPECT_EQ(added[8].devnode, after.fisheye_devnode);

  // What the service does on "added": open it again by its serial; then the new port's removal is seen.
  EXPECT_EQ(findCamera({camera.serial()}).camera_usb.syspath, after.camera);
  testbed().unplug(after);
  expectSame(takeSeen(), expectedRemoval(after));
}

TEST_F(HotplugMonitorTest, AnotherCameraIsIgnored) {
  testbed().add({});
  watch(findCamera({}));
  FakeZr300 other = elsewhere();
  other.serial = "SN_3511803652";
  testbed().unplug(testbed().add(other));
  EXPECT_TRUE(takeSeen().empty());
  EXPECT_EQ(monitor().counters().reported, 0u);
  EXPECT_EQ(monitor().counters().ignored, 22u);  // 3 USB devices and 8 video nodes, each added and removed
}

TEST_F(HotplugMonitorTest, NextNeverBlocksAndTheFdSignalsEvents) {
  const FakeZr300Paths paths = testbed().add({});
  HotplugMonitor monitor(findCamera({}));
  pollfd readable{monitor.fd(), POLLIN, 0};
  EXPECT_EQ(poll(&readable, 1, 0), 0);

  HotplugEvent event;
  event.part = Zr300Part::kAdapterVideoNode;
  const auto start = std::chrono::steady_clock::now();
  EXPECT_FALSE(monitor.next(event));
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(50));
  EXPECT_EQ(partName(event.part), partName(Zr300Part::kAdapterVideoNode));  // untouched

  testbed().uevent(paths.camera, "remove");
  ASSERT_EQ(poll(&readable, 1, 1000), 1);
  EXPECT_TRUE(readable.revents & POLLIN);
  ASSERT_TRUE(monitor.next(event));
  EXPECT_EQ(partName(event.part), partName(Zr300Part::kCamera));
  EXPECT_EQ(actionName(event.action), "removed");
  EXPECT_EQ(poll(&readable, 1, 0), 0);
}

TEST_F(HotplugMonitorTest, NextAllocatesNothing) {
  const FakeZr300Paths paths = testbed().add({});
  HotplugMonitor monitor(findCamera({}));
  for (const std::string& node : paths.camera_video_nodes) testbed().uevent(node, "remove");
  testbed().uevent(paths.camera, "remove");
  testbed().uevent(paths.hub, "remove");  // ignored: read and dropped inside next()
  std::array<HotplugEvent, 16> events;
  std::size_t count = 0;
  const std::uint64_t allocations_before = vifusion::test::heapAllocationCount();
  while (count < events.size() && monitor.next(events[count])) ++count;
  const std::uint64_t allocations = vifusion::test::heapAllocationCount() - allocations_before;
  EXPECT_EQ(count, 7u);
  EXPECT_EQ(monitor.counters().ignored, 1u);
  EXPECT_EQ(allocations, 0u);
}

TEST_F(HotplugMonitorTest, AnAdapterSeenBeforeItsHubIsKnownIsFollowedAfterFollow) {
  const FakeZr300Paths before = testbed().add({});
  const Zr300Camera camera = findCamera({});
  watch(camera);
  testbed().unplug(before);
  takeSeen();

  // The adapter board announces itself before the camera: its hub is not yet known to be the target's.
  FakeZr300 adapter_first = elsewhere();
  adapter_first.camera_present = false;
  const FakeZr300Paths adapter_paths = testbed().add(adapter_first);
  testbed().addFromString(  // the camera on the adapter's hub (add() would create the hub again)
      "P: " + devpathOf(adapter_paths.hub) +
      "/3-1.1\nN: bus/usb/003/099\nE: DEVNAME=/dev/bus/usb/003/099\n"
      "E: DEVTYPE=usb_device\nE: SUBSYSTEM=usb\nA: idVendor=8086\nA: idProduct=0acb\nA: busnum=3\nA: devnum=99\n"
      "A: serial=SN_4071801153\n");
  const std::vector<Seen> added = takeSeen();
  ASSERT_EQ(added.size(), 1u);
  EXPECT_EQ(partName(added[0].part), partName(Zr300Part::kCamera));
  EXPECT_EQ(added[0].devpath, devpathOf(adapter_paths.hub) + "/3-1.1");

  // After re-opening (here only selected: this camera has no video nodes yet), the scan knows the adapter.
  monitor().follow(selectCamera(findCameras(), {camera.serial()}));
  testbed().uevent(adapter_paths.adapter, "remove");
  const std::vector<Seen> removed = takeSeen();
  ASSERT_EQ(removed.size(), 1u);
  EXPECT_EQ(partName(removed[0].part), partName(Zr300Part::kAdapter));
  EXPECT_EQ(removed[0].devpath, devpathOf(adapter_paths.adapter));
}

TEST_F(HotplugMonitorTest, ACameraWithoutSerialIsKnownByItsHub) {
  FakeZr300 no_serial;
  no_serial.serial = "";
  const FakeZr300Paths paths = testbed().add(no_serial);
  watch(findCamera({}));
  testbed().unplug(paths);
  ASSERT_EQ(takeSeen().size(), 10u);

  const FakeZr300Paths same_port = testbed().add(no_serial);
  EXPECT_EQ(takeSeen().size(), 10u);
  testbed().unplug(same_port);
  EXPECT_EQ(takeSeen().size(), 10u);

  // In another port nothing tells it from another camera without serial.
  FakeZr300 moved = elsewhere();
  moved.serial = "";
  testbed().add(moved);
  EXPECT_TRUE(takeSeen().empty());
}

TEST_F(HotplugMonitorTest, AnOverlongDevpathIsCountedAndNamed) {
  testbed().add({});
  watch(findCamera({}));
  // Path components of at most 255 bytes (the file system's limit), 530 bytes in all; adding it announces it.
  const std::string devpath =
      "/devices/" + std::string(250, 'a') + "/" + std::string(250, 'b') + "/video4linux/video99";
  testbed().addFromString("P: " + devpath + "\nE: SUBSYSTEM=video4linux\nA: index=0\n");
  EXPECT_TRUE(takeSeen().empty());
  EXPECT_EQ(monitor().counters().malformed, 1u);
  EXPECT_EQ(monitor().lastProblem(), "uevent add video4linux: DEVPATH has 530 bytes, more than 511");
}

}  // namespace
}  // namespace vifusion::discovery::test
