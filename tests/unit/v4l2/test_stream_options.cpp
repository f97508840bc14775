#include <gtest/gtest.h>

#include "vifusion/test/expect_error.hpp"
#include "vifusion/v4l2/v4l2_stream_options.hpp"

namespace vifusion::v4l2 {
namespace {

V4l2StreamOptions depthOptions() {
  V4l2StreamOptions options;
  options.label = "depth";
  options.node_path = "/dev/video1";
  options.fourcc = kFourccZ16;
  options.width_px = 628;
  options.height_px = 469;
  options.fps = 30;
  options.buffer_count = 4;
  options.timing.exposure_ns = 10'000'000;
  return options;
}

TEST(V4l2StreamOptions, DefaultsAndTheDepthPresetAreValid) {
  V4l2StreamOptions defaults;
  defaults.node_path = "/dev/video2";
  EXPECT_NO_THROW(defaults.validate());
  EXPECT_NO_THROW(depthOptions().validate());
}

TEST(V4l2StreamOptions, EachBadFieldIsNamedWithItsValue) {
  using vifusion::test::expectError;
  auto options = depthOptions();
  options.node_path.clear();
  expectError([&] { options.validate(); }, "V4l2StreamOptions.node_path is empty (depth stream)");
  options = depthOptions();
  options.fourcc = makeFourcc('M', 'J', 'P', 'G');
  expectError([&] { options.validate(); }, "V4l2StreamOptions.fourcc 'MJPG' is not a format");
  options = depthOptions();
  options.width_px = 0;
  expectError([&] { options.validate(); }, "V4l2StreamOptions.width_px = 0 is outside [1, 16384]");
  options = depthOptions();
  options.height_px = 20000;
  expectError([&] { options.validate(); }, "V4l2StreamOptions.height_px = 20000 is outside [1, 16384]");
  options = depthOptions();
  options.fps = 0;
  expectError([&] { options.validate(); }, "V4l2StreamOptions.fps = 0 is outside [1, 1000]");
  options = depthOptions();
  options.buffer_count = 1;
  expectError([&] { options.validate(); }, "V4l2StreamOptions.buffer_count = 1 is outside [2, 32]");
  options.buffer_count = 33;
  expectError([&] { options.validate(); }, "V4l2StreamOptions.buffer_count = 33 is outside [2, 32]");
  options = depthOptions();
  options.timing.exposure_ns = 40'000'000;  // longer than a 30 Hz frame
  expectError([&] { options.validate(); }, "V4l2StreamOptions.timing.exposure_ns = 40000000 is outside [0, 33333333]");
  options = depthOptions();
  options.timing.readout_ns = -1;
  expectError([&] { options.validate(); }, "V4l2StreamOptions.timing.readout_ns = -1 is outside");
}

}  // namespace
}  // namespace vifusion::v4l2
