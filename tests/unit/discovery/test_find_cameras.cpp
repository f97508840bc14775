// findCameras() against ZR300s faked in sysfs/udev by umockdev.

#include <gtest/gtest.h>

#include "discovery_fixture.hpp"
#include "vifusion/discovery/find_cameras.hpp"

namespace vifusion::discovery::test {
namespace {

using FindCamerasTest = DiscoveryTest;

TEST_F(FindCamerasTest, FindsNothingOnAnEmptySystem) {
  const CameraScan scan = findCameras();
  EXPECT_TRUE(scan.cameras.empty());
  EXPECT_TRUE(scan.adapters_without_camera.empty());
}

TEST_F(FindCamerasTest, FindsTheCameraItsStreamsAndItsAdapter) {
  const FakeZr300Paths paths = testbed().add({});
  const CameraScan scan = findCameras();
  ASSERT_EQ(scan.cameras.size(), 1u);
  const Zr300Camera& camera = scan.cameras.front();

  EXPECT_EQ(camera.serial(), "SN_4071801153");
  EXPECT_EQ(camera.label(), "ZR300 SN_4071801153");
  EXPECT_EQ(camera.camera_usb.syspath, paths.camera);
  EXPECT_EQ(camera.camera_usb.devpath, paths.camera.substr(4));  // without "/sys"
  EXPECT_EQ(camera.camera_usb.busnum, 4);
  EXPECT_EQ(camera.camera_usb.devnum, 9);  // hub 8, camera 9, adapter 10
  EXPECT_EQ(camera.camera_usb.devnode, "/dev/bus/usb/004/009");
  EXPECT_EQ("/sys" + std::string(camera.hubDevpath()), paths.hub);

  // Colour was registered first (/dev/video0), IR and depth later: only bInterfaceNumber orders them.
  ASSERT_TRUE(camera.hasAllStreams());
  EXPECT_EQ(camera.stream(Zr300Stream::kInfrared).devnode, "/dev/video2");
  EXPECT_EQ(camera.stream(Zr300Stream::kInfrared).interface_number, 0);
  EXPECT_EQ(camera.stream(Zr300Stream::kDepth).devnode, "/dev/video4");
  EXPECT_EQ(camera.stream(Zr300Stream::kDepth).interface_number, 2);
  EXPECT_EQ(camera.stream(Zr300Stream::kColour).devnode, "/dev/video0");
  EXPECT_EQ(camera.stream(Zr300Stream::kColour).interface_number, 4);
  for (std::size_t stream = 0; stream < kZr300StreamCount; ++stream) {
    EXPECT_EQ(camera.capture_nodes[stream].devnode, paths.stream_devnodes[stream]);
  }
  EXPECT_EQ(camera.stream(Zr300Stream::kDepth).syspath, paths.camera_video_nodes[4]);
  EXPECT_EQ(camera.skipped_video_nodes, 3);  // one metadata node per function

  ASSERT_TRUE(camera.adapter.has_value());
  EXPECT_EQ(camera.adapter->usb.syspath, paths.adapter);
  EXPECT_EQ(camera.adapter->usb.devnode, "/dev/bus/usb/004/010");
  EXPECT_EQ(camera.adapter->usb.busnum, 4);
  EXPECT_EQ(camera.adapter->usb.devnum, 10);
  EXPECT_EQ(camera.adapter->usb.serial, "");  // the CX3 adapter has no iSerialNumber
  ASSERT_TRUE(camera.adapter->fisheye.has_value());
  EXPECT_EQ(camera.adapter->fisheye->devnode, "/dev/video6");
  EXPECT_EQ(camera.adapter->fisheye->interface_number, 0);
  EXPECT_TRUE(scan.adapters_without_camera.empty());
}

TEST_F(FindCamerasTest, WithoutMetadataNodesNothingIsSkipped) {
  FakeZr300 old_kernel;
  old_kernel.metadata_nodes = false;  // uvcvideo before Linux 4.16
  testbed().add(old_kernel);
  const CameraScan scan = findCameras();
  ASSERT_EQ(scan.cameras.size(), 1u);
  EXPECT_TRUE(scan.cameras[0].hasAllStreams());
  EXPECT_EQ(scan.cameras[0].skipped_video_nodes, 0);
  EXPECT_EQ(scan.cameras[0].stream(Zr300Stream::kDepth).devnode, "/dev/video2");  // colour 0, IR 1, depth 2
}

TEST_F(FindCamerasTest, TellsTwoCamerasApartAndPairsEachWithItsOwnAdapter) {
  FakeZr300 second;
  second.bus = 3;
  second.hub_port = 1;
  second.serial = "SN_3511803652";
  const FakeZr300Paths first_paths = testbed().add({});
  const FakeZr300Paths second_paths = testbed().add(second);

  const CameraScan scan = findCameras();
  ASSERT_EQ(scan.cameras.size(), 2u);
  // Sorted by serial.
  EXPECT_EQ(scan.cameras[0].serial(), "SN_3511803652");
  EXPECT_EQ(scan.cameras[1].serial(), "SN_4071801153");
  const Zr300Camera& on_bus_3 = scan.cameras[0];
  const Zr300Camera& on_bus_4 = scan.cameras[1];
  EXPECT_EQ(on_bus_3.camera_usb.syspath, second_paths.camera);
  EXPECT_EQ(on_bus_3.camera_usb.busnum, 3);
  ASSERT_TRUE(on_bus_3.adapter && on_bus_4.adapter);
  EXPECT_EQ(on_bus_3.adapter->usb.syspath, second_paths.adapter);
  EXPECT_EQ(on_bus_4.adapter->usb.syspath, first_paths.adapter);
  EXPECT_EQ(on_bus_3.adapter->fisheye->devnode, second_paths.fisheye_devnode);
  EXPECT_EQ(on_bus_4.adapter->fisheye->devnode, first_paths.fisheye_devnode);
  EXPECT_EQ(on_bus_3.stream(Zr300Stream::kDepth).devnode, second_paths.stream_devnodes[1]);
  EXPECT_EQ(on_bus_4.stream(Zr300Stream::kDepth).devnode, first_paths.stream_devnodes[1]);
  EXPECT_NE(first_paths.stream_devnodes[1], second_paths.stream_devnodes[1]);
}

TEST_F(FindCamerasTest, ListsACameraWithoutVideoNodes) {
  FakeZr300 unbound;
  unbound.bound_camera_functions = 0;
  testbed().add(unbound);
  const CameraScan scan = findCameras();
  ASSERT_EQ(scan.cameras.size(), 1u);
  EXPECT_TRUE(scan.cameras[0].capture_nodes.empty());
  EXPECT_EQ(scan.cameras[0].skipped_video_nodes, 0);
  EXPECT_FALSE(scan.cameras[0].hasAllStreams());
  EXPECT_TRUE(scan.cameras[0].adapter.has_value());
}

TEST_F(FindCamerasTest, ListsACameraWithoutItsAdapter) {
  FakeZr300 alone;
  alone.adapter = false;
  testbed().add(alone);
  const CameraScan scan = findCameras();
  ASSERT_EQ(scan.cameras.size(), 1u);
  EXPECT_TRUE(scan.cameras[0].hasAllStreams());
  EXPECT_FALSE(scan.cameras[0].adapter.has_value());
}

TEST_F(FindCamerasTest, AnAdapterWithoutFisheyeNodeHasNoFisheye) {
  FakeZr300 no_fisheye;
  no_fisheye.adapter_video_nodes = false;
  testbed().add(no_fisheye);
  const CameraScan scan = findCameras();
  ASSERT_EQ(scan.cameras.size(), 1u);
  ASSERT_TRUE(scan.cameras[0].adapter.has_value());
  EXPECT_FALSE(scan.cameras[0].adapter->fisheye.has_value());
}

TEST_F(FindCamerasTest, ReportsAnAdapterWhoseCameraDidNotEnumerate) {
  FakeZr300 adapter_only;
  adapter_only.camera_present = false;
  const FakeZr300Paths paths = testbed().add(adapter_only);
  const CameraScan scan = findCameras();
  EXPECT_TRUE(scan.cameras.empty());
  ASSERT_EQ(scan.adapters_without_camera.size(), 1u);
  EXPECT_EQ(scan.adapters_without_camera[0].syspath, paths.adapter);
}

TEST_F(FindCamerasTest, IgnoresOtherUsbCameras) {
  testbed().addOtherUsbCamera(1, 3, "046d", "0825");  // a Logitech webcam
  testbed().addOtherUsbCamera(2, 4, "8086", "0b07");  // a RealSense D435
  EXPECT_TRUE(findCameras().cameras.empty());

  testbed().add({});
  const CameraScan scan = findCameras();
  ASSERT_EQ(scan.cameras.size(), 1u);
  EXPECT_EQ(scan.cameras[0].serial(), "SN_4071801153");
}

TEST_F(FindCamerasTest, ACameraWithoutSerialIsLabelledByItsPath) {
  FakeZr300 no_serial;
  no_serial.serial = "";
  const FakeZr300Paths paths = testbed().add(no_serial);
  const CameraScan scan = findCameras();
  ASSERT_EQ(scan.cameras.size(), 1u);
  EXPECT_EQ(scan.cameras[0].serial(), "");
  EXPECT_EQ(scan.cameras[0].label(), "ZR300 at " + paths.camera + " (no serial)");
}

}  // namespace
}  // namespace vifusion::discovery::test
