#pragma once
// The preprocessing stage on the GPU: raw depth and RGB in, per pyramid level out: filtered metric
// depth, intensity, vertex and normal maps and intensity gradients (DESIGN.md §4.1). Buffers are
// declared in the capacity plan at construction, kernels and bindings are built once, and the
// whole stage is recorded into a command sequence once and submitted every frame.

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "vifusion/core/image.hpp"
#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/gpu/capacity_plan.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/gpu/compute_kernel.hpp"
#include "vifusion/gpu/gpu_context.hpp"
#include "vifusion/gpu/memory_arena.hpp"
#include "vifusion/preprocess/kernel_params.hpp"
#include "vifusion/preprocess/pixel_types.hpp"

namespace vifusion::preprocess {

struct PreprocessOptions {
  PinholeCamera camera;  ///< level-0 intrinsics and image size (depth and colour registered)
  int levels = 3;        ///< pyramid levels, each half the size of the previous
  DepthToMetricParams metric;         ///< width/height are taken from `camera`
  BilateralDepthParams bilateral;     ///< width/height are taken from `camera`
  float pyramid_range_gate_m = 0.09f; ///< depth pyramid: neighbours farther from the centre are ignored [m]
  RgbToIntensityParams intensity;     ///< width/height are taken from `camera`
  NormalMapParams normals;            ///< width/height are set per level
  uint32_t workgroup_size = 16;       ///< square workgroups of workgroup_size² invocations

  /// Throws vifusion::Error naming the field: odd width (packed depth), too many levels for the
  /// image, non-positive scales, sigmas or gates, min depth ≥ max depth.
  void validate() const;
};

/// The steps in recording order; benchmarks record them one at a time.
enum class PreprocessStep { MetricAndIntensity, Bilateral, Pyramids, VerticesAndGradients, Normals };
inline constexpr PreprocessStep kAllPreprocessSteps[] = {PreprocessStep::MetricAndIntensity, PreprocessStep::Bilateral,
                                                        PreprocessStep::Pyramids, PreprocessStep::VerticesAndGradients,
                                                        PreprocessStep::Normals};
const char* preprocessStepName(PreprocessStep step);

/// Buffer ids of one pyramid level (device-local; valid in the arena built from the plan).
struct LevelBuffers {
  gpu::BufferId depth_m;     ///< filtered metric depth, float [m], 0 = invalid
  gpu::BufferId intensity;   ///< float [0..255]
  gpu::BufferId vertices;    ///< VertexPixel, camera frame [m]
  gpu::BufferId normals;     ///< NormalPixel
  gpu::BufferId gradients;   ///< GradientPixel [intensity / px]
};

class PreprocessStage {
 public:
  PreprocessStage(gpu::GpuContext& context, gpu::CapacityPlan& plan, const PreprocessOptions& options);
  ~PreprocessStage();

  /// Creates the kernels and writes their bindings once the arena exists.
  void build(const gpu::MemoryArena& arena);

  /// Packs one frame into the mapped upload buffers (no allocation). Sizes must match the camera.
  void upload(ImageView<const std::uint16_t> depth_raw, ImageView<const Rgb8> rgb) const;

  /// Records every step, ending with a barrier that makes the outputs visible to later kernels,
  /// transfers and the host.
  void record(gpu::CommandRecorder& recorder) const;
  /// Records one step followed by a barrier (benchmarks).
  void recordStep(gpu::CommandRecorder& recorder, PreprocessStep step) const;

  const PreprocessOptions& options() const { return options_; }
  int levels() const { return options_.levels; }
  const PinholeCamera& camera(int level) const { return cameras_[level]; }
  /// Unfiltered metric depth of level 0 (surfel positions come from it).
  gpu::BufferId rawDepth() const { return raw_depth_m_; }
  /// The packed RGB888 upload buffer (surfel colours are read from it).
  gpu::BufferId rgbWords() const { return rgb_words_; }
  const LevelBuffers& level(int level) const { return levels_[level]; }

 private:
  struct Kernels;

  gpu::GpuContext& context_;
  PreprocessOptions options_;
  std::vector<PinholeCamera> cameras_;
  gpu::BufferId depth_words_;
  gpu::BufferId rgb_words_;
  gpu::BufferId raw_depth_m_;
  std::vector<LevelBuffers> levels_;
  const gpu::MemoryArena* arena_ = nullptr;
  std::unique_ptr<Kernels> kernels_;
};

}  // namespace vifusion::preprocess
