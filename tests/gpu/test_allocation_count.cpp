#include <gtest/gtest.h>

#include <random>

#include "vifusion/test/counting_allocations.hpp"
#include "counting_vulkan.hpp"
#include "gpu_test_environment.hpp"
#include "vifusion/test/seven_scenes_frame.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/preprocess/preprocess_stage.hpp"
#include "vifusion/reduction/row_reducer.hpp"

namespace vifusion {
namespace {

using test::GpuTest;
using test::vulkanCallCounts;

// After start-up the per-frame path must not allocate GPU memory, create Vulkan objects or touch
// the C++ heap:
// 1000 frames of upload → preprocessing → reduction → readback leave every counter where
// start-up left it. Frames are at 320×240 (two real 7-Scenes frames, decimated) to keep CI fast.
TEST_F(GpuTest, NoVulkanAllocationAfterStartUpOverAThousandFrames) {
  std::vector<test::SevenScenesFrame> frames;
  for (int index : {150, 160}) {
    const test::SevenScenesFrame full = test::loadSevenScenesFrame(index);
    test::SevenScenesFrame half{Image<std::uint16_t>(320, 240), Image<preprocess::Rgb8>(320, 240), full.camera.atLevel(1),
                                 full.T_W_C};
    for (int y = 0; y < 240; ++y) {
      for (int x = 0; x < 320; ++x) {
        half.depth_mm(x, y) = full.depth_mm(2 * x, 2 * y);
        half.rgb(x, y) = full.rgb(2 * x, 2 * y);
      }
    }
    frames.push_back(std::move(half));
  }

  const test::VulkanCallCounts before_start_up = vulkanCallCounts();
  const uint64_t heap_before_start_up = test::heapAllocationCount();
  constexpr uint32_t kRows = 320 * 240;
  gpu::CapacityPlan plan;
  preprocess::PreprocessOptions preprocess_options;
  preprocess_options.camera = frames[0].camera;
  preprocess::PreprocessStage preprocess(context(), plan, preprocess_options);
  RowReducerOptions options;
  options.max_rows = kRows;
  RowReducer reducer(context(), plan, options);
  const auto arena = gpu::MemoryArena::create(context(), plan);
  preprocess.build(*arena);
  reducer.build(*arena);
  auto sequence = gpu::CommandSequence::create(context(), "frame");
  sequence->record([&](gpu::CommandRecorder& recorder) {
    preprocess.record(recorder);
    reducer.record(recorder, kRows);
  });

  const test::VulkanCallCounts after_start_up = vulkanCallCounts();
  // The counter sees start-up, so it would see a per-frame allocation too.
  ASSERT_GT(after_start_up.allocate_memory, before_start_up.allocate_memory);
  ASSERT_GT(after_start_up.create_or_update, before_start_up.create_or_update);
  ASSERT_GT(test::heapAllocationCount(), heap_before_start_up);

  std::mt19937 rng(7);
  std::uniform_real_distribution<float> value(-1.0f, 1.0f);
  const std::span<ResidualRow> rows = reducer.rows();
  sequence->run();  // first submission: drivers may set up lazily
  const uint64_t heap_before_frames = test::heapAllocationCount();
  for (int frame = 0; frame < 1000; ++frame) {
    const test::SevenScenesFrame& input = frames[frame % frames.size()];
    preprocess.upload(input.depth_mm.view(), input.rgb.view());
    rows[frame % kRows].r = value(rng);  // a frame's new input
    rows[frame % kRows].w = 1.0f;
    sequence->run();
    ASSERT_GE(reducer.result().inliers, 1.0);
  }

  const uint64_t heap_after_frames = test::heapAllocationCount();
  const test::VulkanCallCounts after_frames = vulkanCallCounts();
  EXPECT_EQ(heap_after_frames, heap_before_frames) << "C++ heap allocations in the per-frame path";
  EXPECT_EQ(after_frames.allocate_memory, after_start_up.allocate_memory);
  EXPECT_EQ(after_frames.create_or_update, after_start_up.create_or_update);
}

}  // namespace
}  // namespace vifusion
