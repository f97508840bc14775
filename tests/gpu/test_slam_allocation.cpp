// The whole RGB-D pipeline (preprocessing, tracking, fusion, cleanup, compaction, prediction, and loop
// closure in the second run) over hundreds of frames: after start-up no Vulkan memory is allocated, no Vulkan object is
// created or re-bound, no C++ heap allocation is made, and the process heap (malloc, which the Vulkan driver uses too)
// stays flat after a warm-up.

#include <gtest/gtest.h>
#include <malloc.h>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <vector>

#include "counting_vulkan.hpp"
#include "gpu_test_environment.hpp"
#include "rendered_pan.hpp"
#include "vifusion/slam/slam.hpp"
#include "vifusion/test/counting_allocations.hpp"

namespace vifusion {
namespace {

using test::GpuTest;
using test::Pan;
using test::panCalibration;
using test::panFrameIndex;
using test::renderPan;
using test::vulkanCallCounts;

std::size_t mallocInUseBytes() { return mallinfo2().uordblks; }

/// Largest pose errors (relative to the first frame) over the first `frames` frames of `pan`, or nullopt when
/// a frame was lost.
struct PanErrors {
  double translation_m = 0.0;
  double rotation_rad = 0.0;
};
std::optional<PanErrors> trackPan(gpu::GpuContext& context, const RigCalibration& calibration, const Pan& pan,
                                  std::size_t frames) {
  slam::SlamOptions options;
  options.map.capacity = 200'000;
  slam::Slam slam(context, calibration, options);
  PanErrors worst;
  for (std::size_t i = 0; i < frames; ++i) {
    const slam::FrameResult result = slam.process(pan.frames[i]);
    if (result.lost()) return std::nullopt;
    const SE3d T_true = pan.T_W_C[0].inverse() * pan.T_W_C[i];
    const Eigen::Matrix<double, 6, 1> error = (T_true.inverse() * result.T_W_C).log();
    worst.translation_m = std::max(worst.translation_m, error.head<3>().norm());
    worst.rotation_rad = std::max(worst.rotation_rad, error.tail<3>().norm());
  }
  return worst;
}

// Frame-to-model tracking recovers the known motion of rendered frames: every pose relative to the
// first (W is the first camera frame) within 3 mm and 0.1°.
TEST_F(GpuTest, RgbdSlamFollowsARenderedPan) {
  const RigCalibration calibration = panCalibration();
  const std::optional<PanErrors> errors = trackPan(context(), calibration, renderPan(calibration.camera), 20);
  ASSERT_TRUE(errors.has_value()) << "lost";
  EXPECT_LT(errors->translation_m, 3e-3);
  EXPECT_LT(errors->rotation_rad, 0.1 * M_PI / 180.0);
}

// The pan with depth from a second camera 30 mm beside the colour camera, turned by 1°, with other
// intrinsics (a ZR300's IR pair): preprocessing registers depth to colour from the calibration's depth
// camera. The warp rounds each depth sample to the nearest colour pixel, moving it by up to half a pixel
// (≈ 5 mm at 1.2 m and f = 120 px here, a quarter of that at 640 × 480), so the bound is 5 mm and 0.15°
// where registered frames get 3 mm and 0.1°. Taken as if registered, the same frames put every depth
// sample ≈ 3 px off its colour and at the wrong bearing, and tracking is far worse.
TEST_F(GpuTest, RgbdSlamFollowsAPanWhoseDepthComesFromASecondCamera) {
  RigCalibration calibration = panCalibration();
  calibration.depth_camera =
      DepthCameraCalibration{PinholeCamera::create(160, 120, 128.0, 129.0, 81.0, 58.5),
                             SE3d(Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 180.0, Eigen::Vector3d::UnitY())),
                                  Eigen::Vector3d(0.03, 0.0, 0.0))};
  const Pan pan = renderPan(calibration.camera, *calibration.depth_camera);
  constexpr std::size_t kFrames = 20;
  const std::optional<PanErrors> registered = trackPan(context(), calibration, pan, kFrames);
  ASSERT_TRUE(registered.has_value()) << "lost with registration";
  EXPECT_LT(registered->translation_m, 5e-3);
  EXPECT_LT(registered->rotation_rad, 0.15 * M_PI / 180.0);

  calibration.depth_camera.reset();
  const std::optional<PanErrors> unregistered = trackPan(context(), calibration, pan, kFrames);
  // (measured: 3.0 mm and 0.06° registered, 15 mm and 0.18° unregistered)
  if (unregistered) {
    EXPECT_GT(unregistered->translation_m, 3.0 * registered->translation_m);
  }
}

/// Runs `frames` frames of the rendered pan (back and forth, so the surfaces seen first go inactive and come back
/// into view) and counts heap allocations after a 50-frame warm-up, on every frame, those whose loop closure
/// reached the deformation graph's solve included.
struct AllocationRun {
  std::uint64_t heap_after_warm_up = 0;  ///< C++ heap allocations in the frames after the warm-up
  int deformations = 0;                  ///< frames whose closure reached the deformation graph's solve
  int accepted = 0;
  int map_to_odom_jumps = 0;  ///< frames whose FrameResult::T_W_O differs from the previous frame's
  int lost = 0;
  long long malloc_growth_bytes = 0;
  test::VulkanCallCounts after_start_up, after_frames;
};

AllocationRun runPan(gpu::GpuContext& context, const slam::SlamOptions& options, int frames) {
  const RigCalibration calibration = panCalibration();
  const Pan rendered = renderPan(calibration.camera);
  const std::vector<RgbdFrame>& pan = rendered.frames;
  slam::Slam slam(context, calibration, options);
  AllocationRun run;
  run.after_start_up = vulkanCallCounts();
  constexpr int kWarmUp = 50;
  std::size_t malloc_after_warm_up = 0;
  RgbdFrame frame;
  SE3d T_W_O;
  for (int i = 0; i < frames; ++i) {
    const RgbdFrame& source = pan[panFrameIndex(static_cast<std::size_t>(i), pan.size())];
    if (i == 0) frame = source;  // the one copy that sizes the frame's images
    std::copy(source.depth.data(), source.depth.data() + source.depth.pixelCount(), frame.depth.data());
    std::copy(source.rgb.data(), source.rgb.data() + source.rgb.pixelCount(), frame.rgb.data());
    frame.t_ns = i * 33'333'333LL;
    frame.index = i;
    if (i == kWarmUp) malloc_after_warm_up = mallocInUseBytes();
    const std::uint64_t heap_before = test::heapAllocationCount();
    const slam::FrameResult result = slam.process(frame);
    const std::uint64_t heap = test::heapAllocationCount() - heap_before;
    const bool deformed = result.closure.nodes > 0;
    run.deformations += deformed ? 1 : 0;
    run.accepted += result.closure.outcome == slam::ClosureOutcome::kAccepted ? 1 : 0;
    run.map_to_odom_jumps += (result.T_W_O.inverse() * T_W_O).log().norm() > 0.0 ? 1 : 0;
    T_W_O = result.T_W_O;
    if (i >= kWarmUp) run.heap_after_warm_up += heap;
    run.lost += result.lost() ? 1 : 0;
  }
  run.after_frames = vulkanCallCounts();
  run.malloc_growth_bytes = static_cast<long long>(mallocInUseBytes()) - static_cast<long long>(malloc_after_warm_up);
  return run;
}

void expectNoPerFrameAllocation(const AllocationRun& run) {
  EXPECT_EQ(run.after_frames.allocate_memory, run.after_start_up.allocate_memory);
  EXPECT_EQ(run.after_frames.create_or_update, run.after_start_up.create_or_update);
  EXPECT_EQ(run.heap_after_warm_up, 0u) << "C++ heap allocations in the per-frame path";
  // The pipeline really ran: the pan is tracked, not lost, so every frame went through fusion.
  EXPECT_EQ(run.lost, 0);
}

// Open-loop odometry: nothing at all is allocated per frame, and malloc's in-use bytes stay flat (they may move
// by a few blocks the driver recycles; 500 frames of any per-frame allocation would grow them far beyond 64 KiB).
TEST_F(GpuTest, RgbdSlamAllocatesNothingOverFiveHundredFrames) {
  slam::SlamOptions options;
  options.map.capacity = 200'000;
  options.loop.enabled = false;
  constexpr int kFrames = 500;
  const AllocationRun run = runPan(context(), options, kFrames);
  expectNoPerFrameAllocation(run);
  EXPECT_LT(run.malloc_growth_bytes, 64 * 1024) << "bytes";
}

// With loop closure: the closure attempts (inactive rendering, registration, refusals) and the closures that
// deform the map (node sampling, the graph's sparse solve, the GPU deformation and reactivation) allocate
// nothing either, and no Vulkan memory or binding is created at any frame. The pan comes back to surfaces that
// went inactive, so closures are tried and deform the map (asserted: the count must not be of an idle path).
TEST_F(GpuTest, RgbdSlamWithLoopClosuresAllocatesNothing) {
  // The pan's ends are seen again every 78 frames: a 30-frame time window lets them go inactive in between,
  // and 260 frames hold three such returns after the warm-up (a closure is not accepted at every return).
  constexpr std::uint32_t kShortTimeWindowFrames = 30;
  constexpr int kFrames = 260;
  slam::SlamOptions options;
  options.map.capacity = 200'000;
  options.map.time_window_frames = kShortTimeWindowFrames;
  // The rendered pan does not drift: its corrections are all within their noise and would only reactivate
  // (ClosureOutcome::kAgreed). Every accepted registration deforms here, so the deformation path is what is
  // counted.
  options.loop.registration.min_correction_chi2.fill(1e-12);
  const AllocationRun run = runPan(context(), options, kFrames);
  expectNoPerFrameAllocation(run);
  EXPECT_GT(run.deformations, 0) << "no closure reached the deformation";
  // REP-105's map → odom moves at an accepted closure and only then (odom → camera stays continuous).
  EXPECT_EQ(run.map_to_odom_jumps, run.accepted);
  std::printf("pan with loop closure: %d deformation solves, %d accepted\n", run.deformations, run.accepted);
}

}  // namespace
}  // namespace vifusion
