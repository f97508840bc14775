// The whole RGB-D pipeline (preprocessing, tracking, fusion, cleanup, compaction, prediction) over
// 500 frames: after start-up no Vulkan memory is allocated, no Vulkan object is created or
// re-bound, no C++ heap allocation is made, and the process heap (malloc, which the Vulkan driver
// uses too) stays flat after a warm-up.

#include <gtest/gtest.h>
#include <malloc.h>

#include <algorithm>
#include <vector>

#include "vifusion/test/counting_allocations.hpp"
#include "counting_vulkan.hpp"
#include "gpu_test_environment.hpp"
#include "rendered_pan.hpp"
#include "vifusion/slam/slam.hpp"

namespace vifusion {
namespace {

using test::GpuTest;
using test::Pan;
using test::panCalibration;
using test::panFrameIndex;
using test::renderPan;
using test::vulkanCallCounts;

std::size_t mallocInUseBytes() { return mallinfo2().uordblks; }

// Frame-to-model tracking recovers the known motion of rendered frames: every pose relative to the
// first (W is the first camera frame) within 3 mm and 0.1°.
TEST_F(GpuTest, RgbdSlamFollowsARenderedPan) {
  const RigCalibration calibration = panCalibration();
  const Pan pan = renderPan(calibration.camera);
  slam::SlamOptions options;
  options.map.capacity = 200'000;
  slam::Slam slam(context(), calibration, options);
  for (std::size_t i = 0; i < 20; ++i) {
    const slam::FrameResult result = slam.process(pan.frames[i]);
    ASSERT_FALSE(result.lost()) << "frame " << i;
    const SE3d T_true = pan.T_W_C[0].inverse() * pan.T_W_C[i];
    const Eigen::Matrix<double, 6, 1> error = (T_true.inverse() * result.T_W_C).log();
    EXPECT_LT(error.head<3>().norm(), 3e-3) << "frame " << i << " translation [m]";
    EXPECT_LT(error.tail<3>().norm(), 0.1 * M_PI / 180.0) << "frame " << i << " rotation [rad]";
  }
}

TEST_F(GpuTest, RgbdSlamAllocatesNothingOverFiveHundredFrames) {
  const RigCalibration calibration = panCalibration();
  const Pan rendered = renderPan(calibration.camera);
  const std::vector<RgbdFrame>& pan = rendered.frames;

  slam::SlamOptions options;
  options.map.capacity = 200'000;
  slam::Slam slam(context(), calibration, options);
  const test::VulkanCallCounts after_start_up = vulkanCallCounts();

  constexpr int kFrames = 500;
  constexpr int kWarmUp = 50;
  uint64_t heap_after_warm_up = 0;
  std::size_t malloc_after_warm_up = 0;
  int lost = 0;
  RgbdFrame frame;
  for (int i = 0; i < kFrames; ++i) {
    const RgbdFrame& source = pan[panFrameIndex(static_cast<std::size_t>(i), pan.size())];
    if (i == 0) frame = source;  // the one copy that sizes the frame's images
    std::copy(source.depth.data(), source.depth.data() + source.depth.pixelCount(), frame.depth.data());
    std::copy(source.rgb.data(), source.rgb.data() + source.rgb.pixelCount(), frame.rgb.data());
    frame.t_ns = i * 33'333'333LL;
    frame.index = i;
    if (i == kWarmUp) {
      heap_after_warm_up = test::heapAllocationCount();
      malloc_after_warm_up = mallocInUseBytes();
    }
    const slam::FrameResult result = slam.process(frame);
    lost += result.lost() ? 1 : 0;
  }
  const test::VulkanCallCounts after_frames = vulkanCallCounts();
  EXPECT_EQ(after_frames.allocate_memory, after_start_up.allocate_memory);
  EXPECT_EQ(after_frames.create_or_update, after_start_up.create_or_update);
  EXPECT_EQ(test::heapAllocationCount(), heap_after_warm_up) << "C++ heap allocations in the per-frame path";
  // malloc's in-use bytes may move by a few blocks the driver recycles; 500 frames of any per-frame
  // allocation that is not freed would grow it far beyond 64 KiB.
  const auto growth = static_cast<long long>(mallocInUseBytes()) - static_cast<long long>(malloc_after_warm_up);
  EXPECT_LT(growth, 64 * 1024) << "bytes";
  // The pipeline really ran: the pan is tracked, not lost, so every frame went through fusion.
  EXPECT_EQ(lost, 0);
}

}  // namespace
}  // namespace vifusion
