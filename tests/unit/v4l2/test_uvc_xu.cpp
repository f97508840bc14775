#include <fcntl.h>
#include <gtest/gtest.h>

#include <cerrno>
#include <vector>

#include "scripted_zr300.hpp"
#include "vifusion/test/expect_error.hpp"
#include "vifusion/v4l2/device_error.hpp"
#include "vifusion/v4l2/scoped_fd.hpp"
#include "vifusion/v4l2/uvc_xu.hpp"

namespace vifusion::v4l2::test {
namespace {

using v4l2_scripted::ManualClock;
using v4l2_scripted::ScriptedV4l2Device;
using vifusion::test::expectError;

constexpr std::uint8_t kUnit = 2;

TEST(UvcXu, Ds4ControlsReadAndWriteTheirDocumentedBytes) {
  ManualClock clock;
  ScriptedV4l2Device device(clock);
  device.addNode(infraredNodeConfig());
  ScopedFd node(device, kInfraredPath, O_RDWR);

  EXPECT_EQ(ds4::depthUnitsUm(device, node.get()), 1000u);  // 0xE8 0x03 0x00 0x00 little-endian
  ds4::setDepthUnitsUm(device, node.get(), 0x00012345);
  EXPECT_EQ(device.controlValue(kInfraredPath, kUnit, 4), (std::vector<std::uint8_t>{0x45, 0x23, 0x01, 0x00}));
  EXPECT_EQ(ds4::depthUnitsUm(device, node.get()), 0x00012345u);

  ds4::setStreamIntent(device, node.get(), ds4::kIntentDepth | ds4::kIntentColour);
  EXPECT_EQ(device.controlValue(kInfraredPath, kUnit, 3), (std::vector<std::uint8_t>{0x05}));

  ds4::setEmitterEnabled(device, node.get(), true);
  EXPECT_EQ(device.controlValue(kInfraredPath, kUnit, 8), (std::vector<std::uint8_t>{0x01}));
  EXPECT_TRUE(ds4::emitterOnWhileStreaming(device, node.get()));
  ds4::setEmitterEnabled(device, node.get(), false);
  EXPECT_FALSE(ds4::emitterOnWhileStreaming(device, node.get()));
  EXPECT_EQ(device.ruleViolations(), 0);
}

TEST(UvcXu, ErrorsNameTheControlAndWhatWentWrong) {
  ManualClock clock;
  ScriptedV4l2Device device(clock);
  auto config = infraredNodeConfig();
  config.controls = {{kUnit, 4, {0xE8, 0x03}, true},  // depth units with the wrong size
                     {kUnit, 3, {0}, false}};         // stream intent read-only
  device.addNode(config);
  ScopedFd node(device, kInfraredPath, O_RDWR);

  expectError([&] { ds4::setEmitterEnabled(device, node.get(), true); },
              "UVC XU control 'DS4 emitter' (unit 2, selector 8, 1 bytes) SET_CUR failed (the device has no such "
              "control): ENOENT");
  expectError([&] { ds4::depthUnitsUm(device, node.get()); },
              "UVC XU control 'DS4 depth units' (unit 2, selector 4, 4 bytes) GET_CUR failed (the device's control "
              "has another size): ENOBUFS");
  expectError([&] { ds4::setStreamIntent(device, node.get(), ds4::kIntentDepth); }, "'DS4 stream intent'");
  try {
    ds4::setStreamIntent(device, node.get(), ds4::kIntentDepth);
    FAIL() << "no DeviceError";
  } catch (const DeviceError& error) {
    EXPECT_EQ(error.errorNumber(), EIO);
  }
  expectError([&] { ds4::setDepthUnitsUm(device, node.get(), 0); }, "DS4 depth units: 0 µm per unit");
  std::vector<std::uint8_t> wrong_size(3);
  expectError([&] { xuGetCurrent(device, node.get(), ds4::kDepthUnits, wrong_size); },
              "GET_CUR: value buffer holds 3 bytes");
}

TEST(UvcXu, AnUnpluggedCameraIsReportedAsGone) {
  ManualClock clock;
  ScriptedV4l2Device device(clock);
  device.addNode(infraredNodeConfig());
  ScopedFd node(device, kInfraredPath, O_RDWR);
  device.unplug();
  try {
    ds4::depthUnitsUm(device, node.get());
    FAIL() << "no DeviceError";
  } catch (const DeviceError& error) {
    EXPECT_TRUE(error.deviceGone());
    EXPECT_NE(std::string(error.what()).find("ENODEV"), std::string::npos) << error.what();
  }
  expectError([&] { ScopedFd missing(device, kInfraredPath, O_RDWR); }, "/dev/video0: cannot open: ENOENT");
}

}  // namespace
}  // namespace vifusion::v4l2::test
