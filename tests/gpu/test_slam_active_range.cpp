// The map's active range end to end (map/map_buffers.hpp): with a 20-frame time window the pan's ends turn
// inactive before the camera returns, and Slam's maintenance retires them to the inactive prefix, which the
// per-frame passes skip. After every frame the active range holds exactly the active surfels (so nothing the
// frame needs was skipped, and nothing inactive is visited twice), a whole-map visit (what a loop closure's
// reactivation asks for) re-partitions it the same way, tracking stays on the pan, and the map update's GPU
// stages are timed wherever the device has timestamps.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "gpu_test_environment.hpp"
#include "rendered_pan.hpp"
#include "vifusion/slam/slam.hpp"

namespace vifusion {
namespace {

using test::GpuTest;

/// Active surfels after frame `frame` in the inactive prefix [0, surfels − active) and in the whole map.
struct ActiveCount {
  std::size_t in_prefix = 0;
  std::size_t in_map = 0;
};
ActiveCount countActive(const std::vector<map::Surfel>& surfels, const slam::FrameResult& result, std::uint32_t frame,
                        std::uint32_t window) {
  ActiveCount count;
  for (std::size_t i = 0; i < surfels.size(); ++i) {
    const bool active = frame - static_cast<std::uint32_t>(surfels[i].colour_times.z()) <= window;
    count.in_map += active ? 1 : 0;
    count.in_prefix += active && i < result.surfels - result.active_surfels ? 1 : 0;
  }
  return count;
}

TEST_F(GpuTest, InactiveSurfelsLeaveTheActiveRangeAndNothingActiveIsSkipped) {
  const RigCalibration calibration = test::panCalibration();
  const test::Pan pan = test::renderPan(calibration.camera);
  slam::SlamOptions options;
  options.map.time_window_frames = 20;
  slam::Slam slam(context(), calibration, options);

  constexpr std::uint32_t kFrames = 120;
  constexpr std::uint32_t kWholeMapVisit = 90;  // the frame before it asks for one
  constexpr std::uint32_t kCheckEvery = 10;
  const bool timestamps = context().features().timestamp_valid_bits > 0;
  std::vector<map::Surfel> surfels;
  slam::FrameResult result;
  double max_translation_m = 0.0;
  int lost = 0, timed = 0;
  RgbdFrame frame;
  for (std::uint32_t i = 0; i < kFrames; ++i) {
    const std::size_t k = test::panFrameIndex(i, pan.frames.size());
    frame = pan.frames[k];
    frame.t_ns = static_cast<std::int64_t>(i) * 33'333'333LL;
    frame.index = i;
    if (i == kWholeMapVisit) slam.map().visitWholeMapNextFrame(slam.arena());
    result = slam.process(frame);
    lost += result.lost() ? 1 : 0;
    const SE3d T_true = pan.T_W_C[0].inverse() * pan.T_W_C[k];
    max_translation_m = std::max(max_translation_m, (T_true.translation() - result.T_W_C.translation()).norm());
    ASSERT_LE(result.active_surfels, result.surfels);
    if (i > 0 && result.map_stages.prediction_ms >= 0.0) {
      ++timed;
      EXPECT_GE(result.map_stages.fusion_ms, 0.0);
      EXPECT_GE(result.map_stages.maintenance_ms, 0.0);
      EXPECT_GE(result.map_stages.reference_ms, 0.0);
    }
    if (i % kCheckEvery == 0 || i == kWholeMapVisit) {
      slam.exportMap(surfels);
      ASSERT_EQ(surfels.size(), result.surfels);
      // The frame's maintenance retired every surfel it found inactive: the active range is exactly the
      // active surfels, and the prefix holds none.
      const ActiveCount active = countActive(surfels, result, i, options.map.time_window_frames);
      EXPECT_EQ(active.in_prefix, 0u) << "frame " << i;
      EXPECT_EQ(active.in_map, result.active_surfels) << "frame " << i;
    }
  }
  std::printf(
      "after %u frames: %u surfels, %u in the active range; largest position error %.2f mm; %d frames "
      "timed on the GPU\n",
      kFrames, result.surfels, result.active_surfels, max_translation_m * 1e3, timed);
  EXPECT_LT(result.active_surfels, result.surfels * 3 / 4) << "the inactive surfels did not leave the active range";
  EXPECT_EQ(lost, 0);
  EXPECT_LT(max_translation_m, 5e-3);
  EXPECT_EQ(timed, timestamps ? static_cast<int>(kFrames) - 1 : 0);
}

}  // namespace
}  // namespace vifusion
