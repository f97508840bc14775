// The map-full policy end to end (map_maintenance.hpp): a map much smaller than what the camera
// sees keeps taking in the view, and tracking stays on the rendered pan.
//
// The pan goes back and forth; with a 30-frame time window the surfels at its ends become stable,
// then inactive before the camera returns, and the returning camera maps them again (inactive
// surfels are neither rendered nor fused), so a 20 k-surfel map fills after ~180 frames with stable
// surfels. Evicting only the never-stable ones frees nothing there (what stopped the 640×480
// living_room_0 map): measured with the age rule switched off, 109 k new surfels were dropped by
// frame 320; with it, none.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "gpu_test_environment.hpp"
#include "rendered_pan.hpp"
#include "vifusion/map/map_maintenance.hpp"
#include "vifusion/slam/slam.hpp"

namespace vifusion {
namespace {

using test::GpuTest;

TEST_F(GpuTest, RgbdSlamKeepsTrackingWhenTheMapIsFull) {
  const RigCalibration calibration = test::panCalibration();
  const test::Pan pan = test::renderPan(calibration.camera);
  slam::SlamOptions options;
  options.map.capacity = 20'000;
  options.map.time_window_frames = 30;  // surfels become stable, then inactive, before the camera returns
  slam::Slam slam(context(), calibration, options);
  const auto full_count = static_cast<std::uint32_t>(map::MaintenanceOptions{}.full_fraction * options.map.capacity);

  constexpr std::size_t kFrames = 320;
  std::uint32_t previous_surfels = 0, max_surfels = 0, dropped = 0;
  std::uint64_t evicted = 0;
  int full_frames = 0, lost = 0;
  double max_translation_m = 0.0, max_rotation_rad = 0.0;
  RgbdFrame frame;
  for (std::size_t i = 0; i < kFrames; ++i) {
    const std::size_t k = test::panFrameIndex(i, pan.frames.size());
    frame = pan.frames[k];
    frame.t_ns = static_cast<std::int64_t>(i) * 33'333'333LL;
    frame.index = static_cast<std::int64_t>(i);
    const slam::FrameResult result = slam.process(frame);
    lost += result.lost() ? 1 : 0;
    const SE3d T_true = pan.T_W_C[0].inverse() * pan.T_W_C[k];
    const Eigen::Matrix<double, 6, 1> error = (T_true.inverse() * result.T_W_C).log();
    max_translation_m = std::max(max_translation_m, error.head<3>().norm());
    max_rotation_rad = std::max(max_rotation_rad, error.tail<3>().norm());
    full_frames += previous_surfels > full_count ? 1 : 0;
    dropped = result.map_overflow;
    evicted += result.map_evicted;
    max_surfels = std::max(max_surfels, result.surfels);
    previous_surfels = result.surfels;
  }
  std::printf("map of %u surfels: at most %u, %d frames began full, %llu evicted, %u new surfels dropped, "
              "%d lost; largest error %.2f mm, %.3f°\n",
              options.map.capacity, max_surfels, full_frames, static_cast<unsigned long long>(evicted), dropped, lost,
              max_translation_m * 1e3, max_rotation_rad * 180.0 / M_PI);
  EXPECT_GE(full_frames, 10) << "the map hardly filled: the test does not test the policy";
  EXPECT_GT(evicted, 0u) << "FrameResult::map_evicted counts the policy's evictions";
  // The headroom above the full mark (5 %, 1000 surfels) takes a frame's new surfels; eviction
  // restores it before the next frame.
  EXPECT_LE(dropped, 1000u) << "the full map stopped taking in the view";
  EXPECT_EQ(lost, 0);
  EXPECT_LT(max_translation_m, 5e-3);
  EXPECT_LT(max_rotation_rad, 0.2 * M_PI / 180.0);
}

}  // namespace
}  // namespace vifusion
