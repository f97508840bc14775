// What RGB-D tracking reports for the frames of a long loss (slam.cpp, TrackerOptions::max_continued_motion_s):
// the camera is covered after a stretch of the rendered pan, so every later frame is lost. Within the recovery
// window the lost frames' pose continues the last tracked motion (the "kept moving" guess a short loss recovers
// from); after it the pose holds, instead of carrying a velocity nobody measures on for as long as the loss
// lasts (what sim:white_wall's lost frames did at 640×480: tests/bench/README.md, issue 15's table re-run).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "gpu_test_environment.hpp"
#include "rendered_pan.hpp"
#include "vifusion/slam/slam.hpp"

namespace vifusion {
namespace {

using test::GpuTest;

constexpr std::int64_t kFramePeriodNs = 33'333'333;

/// The pan's frame with the lens covered: no depth and a black image.
RgbdFrame covered(const RgbdFrame& frame) {
  RgbdFrame dark = frame;
  dark.depth.resize(frame.depth.width(), frame.depth.height(), 0);
  dark.rgb.resize(frame.rgb.width(), frame.rgb.height(), Rgb8{0, 0, 0});
  return dark;
}

TEST_F(GpuTest, LostFramesContinueTheMotionOnlyForTheRecoveryWindowThenHold) {
  const RigCalibration calibration = test::panCalibration();
  const test::Pan pan = test::renderPan(calibration.camera);
  slam::SlamOptions options;
  const double window_s = options.tracker.max_continued_motion_s;
  slam::Slam slam(context(), calibration, options);

  constexpr std::size_t kTrackedFrames = 20;
  const auto lost_frames = static_cast<std::size_t>(std::ceil(2.0 * window_s * 1e9 / kFramePeriodNs));
  const RgbdFrame dark = covered(pan.frames[kTrackedFrames - 1]);
  RgbdFrame frame;
  SE3d T_W_last_tracked;
  std::vector<SE3d> lost_poses;
  for (std::size_t i = 0; i < kTrackedFrames + lost_frames; ++i) {
    frame = i < kTrackedFrames ? pan.frames[i] : dark;
    frame.t_ns = static_cast<std::int64_t>(i) * kFramePeriodNs;
    frame.index = static_cast<std::int64_t>(i);
    const slam::FrameResult result = slam.process(frame);
    if (i < kTrackedFrames) {
      ASSERT_FALSE(result.lost()) << "frame " << i << " of the pan";
      T_W_last_tracked = result.T_W_C;
    } else {
      ASSERT_TRUE(result.lost()) << "covered frame " << i;
      lost_poses.push_back(result.T_W_C);
    }
  }
  // The pan moves 2 mm per frame: inside the window each lost frame carries that step on.
  const double step_m =
      (pan.T_W_C[kTrackedFrames - 1].translation() - pan.T_W_C[kTrackedFrames - 2].translation()).norm();
  SE3d previous = T_W_last_tracked;
  for (std::size_t j = 0; j < lost_poses.size(); ++j) {
    const double moved_m = (lost_poses[j].translation() - previous.translation()).norm();
    const double since_tracked_s = static_cast<double>(j + 1) * kFramePeriodNs * 1e-9;
    if (since_tracked_s <= window_s) {
      EXPECT_NEAR(moved_m, step_m, 0.5 * step_m) << "lost frame " << j + 1 << ", " << since_tracked_s << " s";
    } else {
      EXPECT_LT(moved_m, 1e-9) << "lost frame " << j + 1 << ", " << since_tracked_s << " s: still moving";
    }
    previous = lost_poses[j];
  }
  const double carried_m = (lost_poses.back().translation() - T_W_last_tracked.translation()).norm();
  std::printf("  %zu lost frames; the pose moved %.1f mm in all (%.1f mm per tracked frame)\n", lost_poses.size(),
              carried_m * 1e3, step_m * 1e3);
  EXPECT_LT(carried_m, (window_s * 1e9 / kFramePeriodNs + 1.0) * 1.5 * step_m);
}

}  // namespace
}  // namespace vifusion
