// register_depth.comp against its CPU reference (registerDepthCpu), through the preprocessing stage
// that records it as its first step: bit for bit, on a real Kinect depth frame seen from a made-up
// colour camera and on random depth where many pixels collide, plus the skip for an identity
// registration and the per-frame allocation check.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <iostream>
#include <numbers>
#include <random>

#include "counting_vulkan.hpp"
#include "gpu_test_environment.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/preprocess/cpu_reference.hpp"
#include "vifusion/preprocess/packing.hpp"
#include "vifusion/preprocess/preprocess_stage.hpp"
#include "vifusion/test/counting_allocations.hpp"
#include "vifusion/test/seven_scenes_frame.hpp"

namespace vifusion {
namespace {

using test::GpuTest;

constexpr double kMillimetre_m = 0.001;

/// The ZR300-like pose of a colour camera beside the depth camera: 25 mm to the side, slightly turned.
SE3d colourBesideDepth() {
  return SE3d(Eigen::Quaterniond(
                  Eigen::AngleAxisd(1.5 * std::numbers::pi / 180.0, Eigen::Vector3d(0.3, 1.0, 0.1).normalized())),
              Eigen::Vector3d(-0.025, 0.002, 0.004));
}

preprocess::PreprocessOptions registeringOptions(const PinholeCamera& depth, const PinholeCamera& colour) {
  preprocess::PreprocessOptions options;
  options.camera = colour;
  options.metric.depth_scale_m = static_cast<float>(kMillimetre_m);
  options.registration = preprocess::DepthRegistration{depth, colour, colourBesideDepth(), kMillimetre_m};
  return options;
}

/// The stage with readbacks of its registered raw depth and its metric depth, recorded once.
class RegistrationPipeline {
 public:
  RegistrationPipeline(gpu::GpuContext& context, const preprocess::PreprocessOptions& options)
      : stage_(context, plan_, options) {
    registered_readback_ = readbackOf(stage_.registeredDepthWords());
    metric_readback_ = readbackOf(stage_.rawDepth());
    arena_ = gpu::MemoryArena::create(context, plan_);
    stage_.build(*arena_);
    sequence_ = gpu::CommandSequence::create(context, "registration");
    sequence_->record([&](gpu::CommandRecorder& recorder) {
      stage_.record(recorder);
      copy(recorder, stage_.registeredDepthWords(), registered_readback_);
      copy(recorder, stage_.rawDepth(), metric_readback_);
      recorder.hostReadBarrier();
    });
  }

  void run(const Image<std::uint16_t>& depth, const Image<preprocess::Rgb8>& rgb) {
    stage_.upload(depth.view(), rgb.view());
    sequence_->run();
  }

  /// The GPU's registered raw depth, unpacked into `out` (colour camera size).
  void registered(Image<std::uint16_t>& out) const {
    const auto words = arena_->buffer(registered_readback_).hostSpan<const std::uint32_t>();
    std::size_t i = 0;
    for (int y = 0; y < out.height(); ++y) {
      for (int x = 0; x < out.width(); ++x, ++i) {
        out(x, y) = static_cast<std::uint16_t>(preprocess::depthOfWord(words[i / 2], i));
      }
    }
  }
  ImageView<const float> metric() const {
    const PinholeCamera& camera = stage_.camera(0);
    return {arena_->buffer(metric_readback_).hostSpan<const float>().data(), camera.width, camera.height};
  }
  const preprocess::PreprocessStage& stage() const { return stage_; }

 private:
  gpu::BufferId readbackOf(gpu::BufferId source) {
    const gpu::BufferRequest& request = plan_.buffers()[source.index];
    return plan_.addBuffer(request.name + ".readback", request.bytes, gpu::MemoryUse::Readback);
  }
  void copy(gpu::CommandRecorder& recorder, gpu::BufferId from, gpu::BufferId to) const {
    recorder.copyBuffer(arena_->buffer(from), arena_->buffer(to), arena_->buffer(from).bytes);
  }

  gpu::CapacityPlan plan_;
  preprocess::PreprocessStage stage_;
  gpu::BufferId registered_readback_;
  gpu::BufferId metric_readback_;
  std::unique_ptr<gpu::MemoryArena> arena_;
  std::unique_ptr<gpu::CommandSequence> sequence_;
};

struct Comparison {
  std::size_t mismatches = 0;  ///< pixels whose registered depth differs
  std::size_t filled = 0;      ///< pixels the CPU filled
};

/// Runs `depth` through the GPU stage and the CPU reference and compares registered and metric depth.
Comparison compareWithCpu(RegistrationPipeline& pipeline, const Image<std::uint16_t>& depth) {
  const preprocess::PreprocessOptions& options = pipeline.stage().options();
  const PinholeCamera& colour = options.camera;
  pipeline.run(depth, Image<preprocess::Rgb8>(colour.width, colour.height));
  Image<std::uint16_t> gpu(colour.width, colour.height);
  pipeline.registered(gpu);
  Image<std::uint16_t> cpu(colour.width, colour.height);
  preprocess::registerDepthCpu(depth.view(), options.registration->kernelParams(), cpu.view());
  Image<float> cpu_metric(colour.width, colour.height);
  preprocess::depthToMetricCpu(cpu.view(), options.metric, cpu_metric.view());

  Comparison c;
  const ImageView<const float> gpu_metric = pipeline.metric();
  std::size_t metric_mismatches = 0;
  for (int y = 0; y < colour.height; ++y) {
    for (int x = 0; x < colour.width; ++x) {
      c.mismatches += gpu(x, y) != cpu(x, y);
      c.filled += cpu(x, y) != 0;
      metric_mismatches += gpu_metric(x, y) != cpu_metric(x, y);
    }
  }
  EXPECT_EQ(metric_mismatches, 0u) << "GPU metric depth differs from depth_to_metric of the CPU's registered depth";
  return c;
}

TEST_F(GpuTest, DepthRegistrationMatchesItsCpuReferenceOnRealFrames) {
  const test::SevenScenesFrame first = test::loadSevenScenesFrame(150);
  // A colour camera with other intrinsics than the Kinect depth camera (585, 585, 320, 240).
  const PinholeCamera colour = PinholeCamera::create(640, 480, 540.0, 538.0, 322.5, 236.8);
  RegistrationPipeline pipeline(context(), registeringOptions(first.camera, colour));
  ASSERT_TRUE(pipeline.stage().options().registersDepth());
  for (int index : {150, 175}) {  // two frames through the same recorded sequence
    const test::SevenScenesFrame frame = index == 150 ? first : test::loadSevenScenesFrame(index);
    const Comparison c = compareWithCpu(pipeline, frame.depth_mm);
    EXPECT_EQ(c.mismatches, 0u) << "frame " << index;
    EXPECT_GT(c.filled, 640u * 480u / 2u) << "frame " << index;
    std::cout << "frame " << index << ": " << c.filled << " registered pixels, " << c.mismatches
              << " differ from the CPU\n";
  }
}

// Random depth (10 % holes) at another size than the colour image, registered once to a coarser
// colour camera (about four depth pixels per colour pixel: the z-buffer decides almost everywhere)
// and once to a denser one (holes between landings).
TEST_F(GpuTest, DepthRegistrationMatchesItsCpuReferenceOnRandomDepthWithCollisions) {
  const PinholeCamera depth_camera = PinholeCamera::create(480, 360, 340.0, 340.0, 239.5, 179.5);
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> raw_mm(300, 8000);
  std::bernoulli_distribution hole(0.1);
  Image<std::uint16_t> depth(depth_camera.width, depth_camera.height);
  for (int y = 0; y < depth.height(); ++y) {
    for (int x = 0; x < depth.width(); ++x) depth(x, y) = hole(rng) ? 0 : static_cast<std::uint16_t>(raw_mm(rng));
  }
  for (const PinholeCamera& colour : {PinholeCamera::create(240, 180, 172.0, 171.0, 119.2, 90.3),
                                      PinholeCamera::create(640, 480, 470.0, 470.0, 319.5, 239.5)}) {
    RegistrationPipeline pipeline(context(), registeringOptions(depth_camera, colour));
    const Comparison c = compareWithCpu(pipeline, depth);
    EXPECT_EQ(c.mismatches, 0u) << colour.width << "x" << colour.height;
    // Coarser: nearly every colour pixel gets depth; denser: at most one colour pixel per depth pixel.
    EXPECT_GT(c.filled, static_cast<std::size_t>(colour.width * colour.height) / 3u);
    std::cout << "random depth → " << colour.width << "x" << colour.height << ": " << c.filled << " registered pixels, "
              << c.mismatches << " differ from the CPU\n";
  }
}

TEST_F(GpuTest, DepthRegistrationIsSkippedWhenIdentityAndChecksFrameSizes) {
  const PinholeCamera camera = PinholeCamera::create(64, 48, 50.0, 50.0, 31.5, 23.5);
  gpu::CapacityPlan plain_plan;
  preprocess::PreprocessOptions plain;
  plain.camera = camera;
  preprocess::PreprocessStage plain_stage(context(), plain_plan, plain);

  preprocess::PreprocessOptions identity = plain;
  identity.registration = preprocess::DepthRegistration{camera, camera, SE3d(), 0.001};
  gpu::CapacityPlan identity_plan;
  preprocess::PreprocessStage identity_stage(context(), identity_plan, identity);
  EXPECT_EQ(identity_plan.buffers().size(), plain_plan.buffers().size()) << "an identity registration added buffers";
  EXPECT_EQ(identity_stage.registeredDepthWords().index, plain_stage.registeredDepthWords().index);

  const PinholeCamera depth_camera = PinholeCamera::create(48, 36, 40.0, 40.0, 23.5, 17.5);
  gpu::CapacityPlan plan;
  preprocess::PreprocessStage stage(context(), plan, registeringOptions(depth_camera, camera));
  EXPECT_EQ(plan.buffers().size(), plain_plan.buffers().size() + 2);  // z-buffer and registered depth
  const auto arena = gpu::MemoryArena::create(context(), plan);
  stage.build(*arena);
  const Image<preprocess::Rgb8> rgb(64, 48);
  EXPECT_THROW(stage.upload(Image<std::uint16_t>(64, 48).view(), rgb.view()), Error);  // depth at the colour size
  EXPECT_NO_THROW(stage.upload(Image<std::uint16_t>(48, 36).view(), rgb.view()));
}

// The per-frame path with registration allocates nothing: 60 frames of upload → registration →
// preprocessing leave the heap and the Vulkan object counters where start-up left them.
TEST_F(GpuTest, DepthRegistrationAllocatesNothingPerFrame) {
  const test::SevenScenesFrame full = test::loadSevenScenesFrame(150);
  Image<std::uint16_t> depth(320, 240);
  for (int y = 0; y < 240; ++y) {
    for (int x = 0; x < 320; ++x) depth(x, y) = full.depth_mm(2 * x, 2 * y);
  }
  const PinholeCamera colour = PinholeCamera::create(320, 240, 270.0, 269.0, 161.2, 118.4);
  const Image<preprocess::Rgb8> rgb(320, 240);

  const uint64_t heap_before_start_up = test::heapAllocationCount();
  gpu::CapacityPlan plan;
  preprocess::PreprocessStage stage(context(), plan, registeringOptions(full.camera.atLevel(1), colour));
  const auto arena = gpu::MemoryArena::create(context(), plan);
  stage.build(*arena);
  auto sequence = gpu::CommandSequence::create(context(), "registration frame");
  sequence->record([&](gpu::CommandRecorder& recorder) { stage.record(recorder); });
  ASSERT_GT(test::heapAllocationCount(), heap_before_start_up);  // the counter sees start-up

  sequence->run();  // first submission: drivers may set up lazily
  const test::VulkanCallCounts after_start_up = test::vulkanCallCounts();
  const uint64_t heap_before_frames = test::heapAllocationCount();
  for (int frame = 0; frame < 60; ++frame) {
    depth(frame % 320, 120) = static_cast<std::uint16_t>(1000 + frame);  // a frame's new input
    stage.upload(depth.view(), rgb.view());
    sequence->run();
  }
  EXPECT_EQ(test::heapAllocationCount(), heap_before_frames) << "C++ heap allocations in the per-frame path";
  const test::VulkanCallCounts after_frames = test::vulkanCallCounts();
  EXPECT_EQ(after_frames.allocate_memory, after_start_up.allocate_memory);
  EXPECT_EQ(after_frames.create_or_update, after_start_up.create_or_update);
}

}  // namespace
}  // namespace vifusion
