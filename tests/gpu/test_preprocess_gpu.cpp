// Every preprocessing kernel against its CPU reference on real Kinect frames (7-Scenes), at every
// pyramid level. Each kernel is compared on the SAME input (the GPU result of the step before), so
// a difference is that kernel's own, not one carried down the chain.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "gpu_test_environment.hpp"
#include "vifusion/test/seven_scenes_frame.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/preprocess/cpu_reference.hpp"
#include "vifusion/preprocess/preprocess_stage.hpp"

namespace vifusion {
namespace {

using preprocess::GradientPixel;
using preprocess::NormalPixel;
using preprocess::VertexPixel;
using test::GpuTest;

/// A device-local stage buffer and the readback buffer it is copied into after each run.
struct Mirror {
  gpu::BufferId source;
  gpu::BufferId readback;
};

class PreprocessPipeline {
 public:
  PreprocessPipeline(gpu::GpuContext& context, const preprocess::PreprocessOptions& options)
      : stage_(context, plan_, options) {
    raw_depth_ = mirror(stage_.rawDepth());
    filtered_vertices_ = mirror(stage_.filteredVertices());
    for (int l = 0; l < stage_.levels(); ++l) {
      const preprocess::LevelBuffers& level = stage_.level(l);
      levels_.push_back({mirror(level.depth_m), mirror(level.intensity), mirror(level.vertices), mirror(level.normals),
                         mirror(level.gradients)});
    }
    arena_ = gpu::MemoryArena::create(context, plan_);
    stage_.build(*arena_);
    sequence_ = gpu::CommandSequence::create(context, "preprocess");
    sequence_->record([&](gpu::CommandRecorder& recorder) {
      stage_.record(recorder);
      for (const Mirror& m : mirrors_) recorder.copyBuffer(buffer(m.source), buffer(m.readback), buffer(m.source).bytes);
      recorder.hostReadBarrier();
    });
  }

  void run(const test::SevenScenesFrame& frame) {
    stage_.upload(frame.depth_mm.view(), frame.rgb.view());
    sequence_->run();
  }

  template <typename T>
  ImageView<const T> image(const Mirror& m, int level) const {
    const PinholeCamera& camera = stage_.camera(level);
    return {buffer(m.readback).hostSpan<const T>().data(), camera.width, camera.height};
  }

  struct LevelMirrors {
    Mirror depth, intensity, vertices, normals, gradients;
  };
  const preprocess::PreprocessStage& stage() const { return stage_; }
  const Mirror& rawDepth() const { return raw_depth_; }
  const Mirror& filteredVertices() const { return filtered_vertices_; }
  const LevelMirrors& level(int l) const { return levels_[l]; }

 private:
  Mirror mirror(gpu::BufferId source) {
    const gpu::BufferRequest& request = plan_.buffers()[source.index];
    mirrors_.push_back({source, plan_.addBuffer(request.name + ".readback", request.bytes, gpu::MemoryUse::Readback)});
    return mirrors_.back();
  }
  const gpu::GpuBuffer& buffer(gpu::BufferId id) const { return arena_->buffer(id); }

  gpu::CapacityPlan plan_;
  preprocess::PreprocessStage stage_;
  std::vector<Mirror> mirrors_;
  Mirror raw_depth_;
  Mirror filtered_vertices_;
  std::vector<LevelMirrors> levels_;
  std::unique_ptr<gpu::MemoryArena> arena_;
  std::unique_ptr<gpu::CommandSequence> sequence_;
};

struct Difference {
  double max_abs = 0.0;
  std::size_t validity_mismatches = 0;  ///< pixels valid in one image only
  std::size_t valid = 0;                ///< pixels valid in both
};

double magnitude(float value) { return std::abs(value); }
template <typename Derived>
double magnitude(const Eigen::MatrixBase<Derived>& value) {
  return value.template cast<double>().cwiseAbs().maxCoeff();
}
bool isValid(float value) { return value != 0.0f; }
template <typename Derived>
bool isValid(const Eigen::MatrixBase<Derived>& value) {
  return !value.isZero(0.0);
}

template <typename T>
Difference compare(ImageView<const T> gpu, ImageView<const T> cpu) {
  Difference d;
  for (int y = 0; y < gpu.height; ++y) {
    for (int x = 0; x < gpu.width; ++x) {
      const bool gpu_valid = isValid(gpu(x, y));
      const bool cpu_valid = isValid(cpu(x, y));
      if (gpu_valid != cpu_valid) {
        ++d.validity_mismatches;
        continue;
      }
      if (!gpu_valid) continue;
      ++d.valid;
      d.max_abs = std::max(d.max_abs, magnitude(gpu(x, y) - cpu(x, y)));
    }
  }
  return d;
}

/// Expects GPU and CPU to agree within `tolerance` on pixels valid in both and to disagree on
/// validity for at most `max_mismatch_fraction` of the pixels (a value at a gate's edge may land
/// on either side when the GPU rounds differently); at least `min_valid_fraction` must be valid.
template <typename T>
void expectAgree(const char* what, int level, ImageView<const T> gpu, ImageView<const T> cpu, double tolerance,
                 double max_mismatch_fraction = 0.0, double min_valid_fraction = 0.3) {
  const Difference d = compare(gpu, cpu);
  const double n = static_cast<double>(gpu.pixelCount());
  SCOPED_TRACE(std::string(what) + " level " + std::to_string(level));
  EXPECT_LE(d.max_abs, tolerance);
  EXPECT_LE(static_cast<double>(d.validity_mismatches), max_mismatch_fraction * n);
  EXPECT_GE(static_cast<double>(d.valid), min_valid_fraction * n) << "too few valid pixels for a meaningful test";
  std::cout << what << " L" << level << ": max |gpu − cpu| = " << d.max_abs << ", valid " << d.valid
            << ", validity mismatches " << d.validity_mismatches << "\n";
}

struct CameraCase {
  const char* name;
  double fy_sign;                  ///< −1: ICL-NUIM-style negative fy
  float inverse_depth_bias_per_m;  ///< DepthToMetricParams: the simulated Kinect's 1.42e-3, or none
};
void PrintTo(const CameraCase& c, std::ostream* out) { *out << c.name; }

class PreprocessGpuTest : public GpuTest, public ::testing::WithParamInterface<CameraCase> {};

TEST_P(PreprocessGpuTest, EveryKernelMatchesItsCpuReferenceOnRealFrames) {
  test::SevenScenesFrame frame = test::loadSevenScenesFrame(150);
  frame.camera.fy *= GetParam().fy_sign;
  preprocess::PreprocessOptions options;
  options.camera = frame.camera;
  options.metric.inverse_depth_bias_per_m = GetParam().inverse_depth_bias_per_m;
  PreprocessPipeline pipeline(context(), options);
  const preprocess::PreprocessOptions& used = pipeline.stage().options();

  for (int index : {150, 175}) {  // two frames through the same recorded sequence
    const test::SevenScenesFrame input = index == 150 ? frame : test::loadSevenScenesFrame(index);
    pipeline.run(input);
    const PinholeCamera& camera0 = pipeline.stage().camera(0);

    Image<float> metric(camera0.width, camera0.height);
    preprocess::depthToMetricCpu(input.depth_mm.view(), used.metric, metric.view());
    // Exact without a bias; with one, GLSL's division may be 2.5 ulp off (≈ 1.2e-6 m at 4 m).
    const double metric_tolerance_m = used.metric.inverse_depth_bias_per_m == 0.0f ? 0.0 : 2e-6;
    expectAgree<float>("metric depth", 0, pipeline.image<float>(pipeline.rawDepth(), 0), metric.view(), metric_tolerance_m);

    Image<float> intensity(camera0.width, camera0.height);
    preprocess::rgbToIntensityCpu(input.rgb.view(), used.intensity, intensity.view());
    expectAgree<float>("intensity", 0, pipeline.image<float>(pipeline.level(0).intensity, 0), intensity.view(), 1e-4);

    Image<float> filtered(camera0.width, camera0.height);
    preprocess::bilateralDepthCpu(pipeline.image<float>(pipeline.rawDepth(), 0), used.bilateral, filtered.view());
    expectAgree<float>("bilateral depth", 0, pipeline.image<float>(pipeline.level(0).depth, 0), filtered.view(), 1e-5);

    for (int l = 0; l < pipeline.stage().levels(); ++l) {
      const PinholeCamera& camera = pipeline.stage().camera(l);
      const auto& level = pipeline.level(l);
      if (l > 0) {
        const PinholeCamera& fine = pipeline.stage().camera(l - 1);
        Image<float> depth(camera.width, camera.height);
        preprocess::pyramidDownDepthCpu(pipeline.image<float>(pipeline.level(l - 1).depth, l - 1),
                                        {fine.width, fine.height, used.pyramid_range_gate_m}, depth.view());
        expectAgree<float>("depth pyramid", l, pipeline.image<float>(level.depth, l), depth.view(), 1e-5);
        Image<float> coarse(camera.width, camera.height);
        preprocess::pyramidDownIntensityCpu(pipeline.image<float>(pipeline.level(l - 1).intensity, l - 1),
                                            {fine.width, fine.height}, coarse.view());
        expectAgree<float>("intensity pyramid", l, pipeline.image<float>(level.intensity, l), coarse.view(), 1e-4);
      }
      // Level 0: vertices from the unfiltered depth, normals from the filtered depth's vertices.
      const Mirror& vertex_depth = l == 0 ? pipeline.rawDepth() : level.depth;
      Image<VertexPixel> vertices(camera.width, camera.height, VertexPixel::Zero());
      preprocess::vertexMapCpu(pipeline.image<float>(vertex_depth, l), preprocess::VertexMapParams::fromCamera(camera),
                               vertices.view());
      expectAgree<VertexPixel>("vertices", l, pipeline.image<VertexPixel>(level.vertices, l), vertices.view(), 1e-5);
      if (l == 0) {
        Image<VertexPixel> filtered_vertices(camera.width, camera.height, VertexPixel::Zero());
        preprocess::vertexMapCpu(pipeline.image<float>(level.depth, 0), preprocess::VertexMapParams::fromCamera(camera),
                                 filtered_vertices.view());
        expectAgree<VertexPixel>("filtered vertices", 0, pipeline.image<VertexPixel>(pipeline.filteredVertices(), 0),
                                 filtered_vertices.view(), 1e-5);
      }
      const Mirror& normal_vertices = l == 0 ? pipeline.filteredVertices() : level.vertices;

      Image<NormalPixel> normals(camera.width, camera.height, NormalPixel::Zero());
      preprocess::normalMapCpu(pipeline.image<VertexPixel>(normal_vertices, l), used.normalParams(camera), normals.view());
      expectAgree<NormalPixel>("normals", l, pipeline.image<NormalPixel>(level.normals, l), normals.view(), 1e-4, 1e-4);

      Image<GradientPixel> gradients(camera.width, camera.height, GradientPixel::Zero());
      preprocess::intensityGradientCpu(pipeline.image<float>(level.intensity, l), {camera.width, camera.height},
                                       gradients.view());
      expectAgree<GradientPixel>("gradients", l, pipeline.image<GradientPixel>(level.gradients, l), gradients.view(),
                                 1e-4);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Cameras, PreprocessGpuTest,
                         ::testing::Values(CameraCase{"kinect", 1.0, 0.0f}, CameraCase{"negative_fy", -1.0, 0.0f},
                                           CameraCase{"biased_depth", 1.0, 1.4232849e-3f}),
                         [](const ::testing::TestParamInfo<CameraCase>& info) { return std::string(info.param.name); });

TEST_F(GpuTest, PreprocessRejectsBadOptionsAndMismatchedFrames) {
  preprocess::PreprocessOptions options;
  options.camera = PinholeCamera::create(641, 480, 500, 500, 320, 240);
  gpu::CapacityPlan plan;
  EXPECT_THROW(preprocess::PreprocessStage(context(), plan, options), Error);  // odd width
  options.camera = PinholeCamera::create(64, 48, 50, 50, 32, 24);
  options.levels = 4;  // 64×48 → 8×6 at level 3
  EXPECT_THROW(preprocess::PreprocessStage(context(), plan, options), Error);
  options.levels = 3;
  options.metric.min_depth_m = 5.0f;
  EXPECT_THROW(preprocess::PreprocessStage(context(), plan, options), Error);
  options.metric.min_depth_m = 0.3f;
  options.metric.inverse_depth_bias_per_m = 0.2f;  // beyond kMaxInverseDepthBias_per_m
  EXPECT_THROW(preprocess::PreprocessStage(context(), plan, options), Error);
  options.metric.inverse_depth_bias_per_m = 0.0f;

  preprocess::PreprocessStage stage(context(), plan, options);
  const auto arena = gpu::MemoryArena::create(context(), plan);
  stage.build(*arena);
  Image<std::uint16_t> depth(64, 48);
  Image<preprocess::Rgb8> rgb(32, 48);
  EXPECT_THROW(stage.upload(depth.view(), rgb.view()), Error);
}

}  // namespace
}  // namespace vifusion
