// findCamera(): the camera a source spec names, or the error that says what is missing.

#include <grp.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "discovery_fixture.hpp"
#include "vifusion/discovery/find_cameras.hpp"
#include "vifusion/discovery/select_camera.hpp"

namespace vifusion::discovery::test {
namespace {

using SelectCameraTest = DiscoveryTest;

FakeZr300 secondCamera() {
  FakeZr300 second;
  second.bus = 3;
  second.hub_port = 1;
  second.serial = "SN_3511803652";
  return second;
}

TEST_F(SelectCameraTest, TakesTheOnlyCamera) {
  const FakeZr300Paths paths = testbed().add({});
  const Zr300Camera camera = findCamera({});
  EXPECT_EQ(camera.serial(), "SN_4071801153");
  EXPECT_EQ(camera.stream(Zr300Stream::kDepth).devnode, paths.stream_devnodes[1]);
}

TEST_F(SelectCameraTest, NoCameraAtAll) {
  testbed().addOtherUsbCamera(1, 3, "046d", "0825");
  expectProblem([] { findCamera({}); }, DiscoveryProblem::kNoCamera, "no ZR300 (8086:0acb) on any USB bus");
  const std::string message = expectProblem([] { findCamera({"SN_4071801153"}); }, DiscoveryProblem::kNoCamera,
                                            "no ZR300 (8086:0acb) on any USB bus (looking for serial 'SN_4071801153')");
  EXPECT_EQ(message.find("adapter"), std::string::npos);
}

TEST_F(SelectCameraTest, NoCameraButItsAdapterPointsAtTheCable) {
  FakeZr300 adapter_only;
  adapter_only.camera_present = false;
  const FakeZr300Paths paths = testbed().add(adapter_only);
  expectProblem([] { findCamera({}); }, DiscoveryProblem::kNoCamera,
                "no ZR300 (8086:0acb) on any USB bus; an adapter board 8086:0ad0 is there (" + paths.adapter +
                    ") but its camera did not enumerate: check the cable and use a USB 3 port");
}

TEST_F(SelectCameraTest, SeveralCamerasNeedASerial) {
  testbed().add({});
  testbed().add(secondCamera());
  expectProblem([] { findCamera({}); }, DiscoveryProblem::kAmbiguous,
                "2 ZR300 cameras found (serials SN_3511803652, SN_4071801153): choose one with the source "
                "zr300:SERIAL");
}

TEST_F(SelectCameraTest, ASerialChoosesAmongSeveral) {
  const FakeZr300Paths first = testbed().add({});
  const FakeZr300Paths second = testbed().add(secondCamera());
  EXPECT_EQ(findCamera({"SN_3511803652"}).camera_usb.syspath, second.camera);
  EXPECT_EQ(findCamera({"4071801153"}).camera_usb.syspath, first.camera);  // digits alone
  EXPECT_EQ(findCamera({"SN_4071801153"}).adapter->usb.syspath, first.adapter);
}

TEST_F(SelectCameraTest, AnUnknownSerialListsTheSerialsFound) {
  testbed().add({});
  testbed().add(secondCamera());
  expectProblem([] { findCamera({"SN_1111111111"}); }, DiscoveryProblem::kSerialNotFound,
                "no ZR300 with serial 'SN_1111111111'; found SN_3511803652, SN_4071801153");
}

TEST_F(SelectCameraTest, NoVideoNodesMeansUvcvideoIsNotBound) {
  FakeZr300 unbound;
  unbound.bound_camera_functions = 0;
  const FakeZr300Paths paths = testbed().add(unbound);
  expectProblem([] { findCamera({}); }, DiscoveryProblem::kUvcNotBound,
                "found 8086:0acb (ZR300 SN_4071801153, " + paths.camera +
                    ") but no video4linux nodes under it: the uvcvideo driver is not bound to it");
}

TEST_F(SelectCameraTest, MissingCaptureNodesAreListed) {
  FakeZr300 partly_bound;
  partly_bound.bound_camera_functions = 2;  // colour (interface 4) and IR (interface 0); depth missing
  testbed().add(partly_bound);
  expectProblem([] { findCamera({}); }, DiscoveryProblem::kMissingStreams,
                "with 2 video capture nodes (/dev/video2 at interface 0, /dev/video0 at interface 4), expected 3: "
                "IR, depth and colour in bInterfaceNumber order");
}

TEST_F(SelectCameraTest, AMissingAdapterMeansNoImuUnlessNotRequired) {
  FakeZr300 alone;
  alone.adapter = false;
  const FakeZr300Paths paths = testbed().add(alone);
  expectProblem([] { findCamera({}); }, DiscoveryProblem::kNoAdapter,
                "but no adapter board 8086:0ad0 on its hub (" + paths.hub +
                    "): the IMU (motion module) and the fisheye camera are unavailable");
  CameraCheckOptions rgbd_only;
  rgbd_only.require_adapter = false;
  EXPECT_EQ(findCamera({}, rgbd_only).serial(), "SN_4071801153");
}

TEST_F(SelectCameraTest, ANodeUdevDidNotCreateIsNamed) {
  const FakeZr300Paths paths = testbed().add({});
  // The fake /dev lives in the test bed; without the node there the real /dev (which has none) shows through.
  ASSERT_TRUE(std::filesystem::remove(testbed().rootDir() + paths.stream_devnodes[1]));
  expectProblem([] { findCamera({}); }, DiscoveryProblem::kNodeMissing,
                "sysfs lists " + paths.stream_devnodes[1] +
                    " (ZR300 SN_4071801153 depth node) but it does not exist: udev did not create it");
  CameraCheckOptions listing;
  listing.check_access = false;
  EXPECT_EQ(findCamera({}, listing).stream(Zr300Stream::kDepth).devnode, paths.stream_devnodes[1]);
}

TEST_F(SelectCameraTest, TheAdaptersUsbNodeIsCheckedOnlyWhenTheImuIsRequired) {
  const FakeZr300Paths paths = testbed().add({});
  ASSERT_TRUE(std::filesystem::remove(testbed().rootDir() + paths.adapter_usb_devnode));
  expectProblem([] { findCamera({}); }, DiscoveryProblem::kNodeMissing,
                "sysfs lists " + paths.adapter_usb_devnode + " (ZR300 SN_4071801153 adapter board (IMU) USB node)");
  CameraCheckOptions rgbd_only;
  rgbd_only.require_adapter = false;
  EXPECT_NO_THROW(findCamera({}, rgbd_only));
}

// Permission checks need a process that lacks the permission; root has them all. So these run
// findCamera() in a child (a death test re-runs the test in a fresh process up to the statement) whose
// real and effective ids become nobody's while it looks (access(2) checks the real ids); its saved uid
// stays root, so that it can take root back and remove its test bed before it exits.
constexpr uid_t kNobodyId = 65534;  // nobody/nogroup on Debian

/// Lets everyone traverse the test bed and open every fake node.
void makeNodesUsableByAll(const std::string& root) {
  namespace fs = std::filesystem;
  fs::permissions(root, fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec | fs::perms::others_read |
                            fs::perms::others_exec);
  for (const fs::directory_entry& entry : fs::recursive_directory_iterator(root + "/dev")) {
    if (entry.is_directory()) {
      fs::permissions(entry.path(), fs::perms::all & ~fs::perms::others_write & ~fs::perms::group_write);
    } else {  // umockdev's /dev/video* are links to ptys it opened: this changes the pty, as wanted
      fs::permissions(entry.path(), fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read |
                                        fs::perms::group_write | fs::perms::others_read | fs::perms::others_write);
    }
  }
}

/// Every fake node usable by all, except `denied` (a /dev path), which no one but root may open.
void makeOnlyOneNodeUnusable(const std::string& root, const std::string& denied) {
  makeNodesUsableByAll(root);
  std::filesystem::permissions(root + denied, std::filesystem::perms::none);
}

/// Runs findCamera({}) as nobody (when root), reports on stderr what happened ("[problem] message"), calls
/// `clean_up` as the original user and exits: 0 after a DiscoveryError, 1 after success, 2 on a setup error.
template <class CleanUp>
[[noreturn]] void findCameraAsNobodyAndReport(CleanUp&& clean_up) {
  const bool root = geteuid() == 0;
  if (root && (setgroups(0, nullptr) != 0 || setresgid(kNobodyId, kNobodyId, 0) != 0 ||
               setresuid(kNobodyId, kNobodyId, 0) != 0)) {
    std::perror("becoming nobody");
    _exit(2);
  }
  std::string report = "findCamera() succeeded";
  int exit_code = 1;
  try {
    findCamera({});
  } catch (const DiscoveryError& error) {
    report = "[" + std::string(problemName(error.problem())) + "] " + error.what();
    exit_code = 0;
  }
  if (root && (setresuid(0, 0, 0) != 0 || setresgid(0, 0, 0) != 0)) {
    std::perror("becoming root again");
    _exit(2);
  }
  clean_up();
  std::fputs(report.c_str(), stderr);
  _exit(exit_code);
}

using SelectCameraDeathTest = DiscoveryTest;

TEST_F(SelectCameraDeathTest, PermissionDeniedOnAVideoNodeNamesTheGroupAndTheRule) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");  // umockdev runs threads: no plain fork()
  const FakeZr300Paths paths = testbed().add({});
  EXPECT_EXIT(
      {
        makeOnlyOneNodeUnusable(testbed().rootDir(), paths.stream_devnodes[0]);
        findCameraAsNobodyAndReport([this] { destroyTestbed(); });
      },
      ::testing::ExitedWithCode(0),
      "\\[permission denied\\] permission denied on /dev/video2 \\(ZR300 SN_4071801153 IR node\\): the udev rules "
      "99-vifusion.rules .* give the ZR300's video4linux nodes to group 'video' with mode 0660: run as a member "
      "of 'video'");
}

TEST_F(SelectCameraDeathTest, PermissionDeniedOnTheImuNodeNamesPlugdev) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");  // umockdev runs threads: no plain fork()
  const FakeZr300Paths paths = testbed().add({});
  EXPECT_EXIT(
      {
        makeOnlyOneNodeUnusable(testbed().rootDir(), paths.adapter_usb_devnode);
        findCameraAsNobodyAndReport([this] { destroyTestbed(); });
      },
      ::testing::ExitedWithCode(0),
      "\\[permission denied\\] permission denied on /dev/bus/usb/004/010 \\(ZR300 SN_4071801153 adapter board "
      "\\(IMU\\) USB node\\): .* give the ZR300's USB device nodes to group 'plugdev'");
}

TEST_F(SelectCameraDeathTest, AnUnprivilegedUserWithAccessFindsTheCamera) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");  // umockdev runs threads: no plain fork()
  testbed().add({});
  // The control for the two tests above: the same drop to nobody, every node usable.
  EXPECT_EXIT(
      {
        makeNodesUsableByAll(testbed().rootDir());
        findCameraAsNobodyAndReport([this] { destroyTestbed(); });
      },
      ::testing::ExitedWithCode(1), "findCamera\\(\\) succeeded");
}

}  // namespace
}  // namespace vifusion::discovery::test
