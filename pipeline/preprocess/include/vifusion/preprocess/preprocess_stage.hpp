#pragma once
// The preprocessing stage on the GPU: raw depth and RGB in, per pyramid level out: filtered metric
// depth, intensity, vertex and normal maps and intensity gradients (DESIGN.md §4.1). Buffers are
// declared in the capacity plan at construction, kernels and bindings are built once, and the
// whole stage is recorded into a command sequence once and submitted every frame.

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "vifusion/core/image.hpp"
#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/gpu/capacity_plan.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/gpu/compute_kernel.hpp"
#include "vifusion/gpu/gpu_context.hpp"
#include "vifusion/gpu/memory_arena.hpp"
#include "vifusion/preprocess/depth_registration.hpp"
#include "vifusion/preprocess/kernel_params.hpp"
#include "vifusion/preprocess/pixel_types.hpp"

namespace vifusion::preprocess {

struct PreprocessOptions {
  PinholeCamera camera;  ///< level-0 intrinsics and image size: the colour camera's (depth registered to it)
  /// Set when depth comes from another camera than colour (ZR300): frames then carry depth at
  /// registration->depth's size, and the first step warps it into `camera`'s pixels. Its colour
  /// camera must equal `camera` and its depth scale metric.depth_scale_m. Unset, or an identity
  /// registration (isIdentity()), skips the step: depth is already registered (datasets, simulator).
  std::optional<DepthRegistration> registration;
  int levels = 3;                      ///< pyramid levels, each half the size of the previous
  DepthToMetricParams metric;          ///< width/height are taken from `camera`
  BilateralDepthParams bilateral;      ///< width/height are taken from `camera`
  float pyramid_range_gate_m = 0.09f;  ///< depth pyramid: neighbours farther from the centre are ignored [m]
  RgbToIntensityParams intensity;      ///< width/height are taken from `camera`
  NormalMapParams normals;             ///< width, height and span_px are set per level
  /// Half-baseline of the normals' central differences as a viewing angle [rad]: span_px at a level
  /// is max(1, round(normal_span_rad · fx)), so 4 px at 640 × 480 (fx ≈ 480), 2 px at 320 × 240, and
  /// the normals describe the same surface patch at every resolution and pyramid level.
  float normal_span_rad = 0.012f;
  uint32_t workgroup_size = 16;  ///< square workgroups of workgroup_size² invocations

  /// Throws vifusion::Error naming the field: odd width (packed depth), too many levels for the
  /// image, non-positive scales, sigmas or gates, min depth ≥ max depth.
  void validate() const;

  /// normal_map parameters for the pyramid level whose camera is `level_camera`.
  NormalMapParams normalParams(const PinholeCamera& level_camera) const;

  /// True when a registration is set and is not the identity: the RegisterDepth step runs.
  bool registersDepth() const { return registration.has_value() && !registration->isIdentity(); }
  /// The camera whose pixels the uploaded raw depth is in: registration->depth, or `camera`.
  const PinholeCamera& depthCamera() const { return registration ? registration->depth : camera; }
};

/// The steps in recording order; benchmarks record them one at a time. RegisterDepth records nothing
/// unless PreprocessOptions::registersDepth().
enum class PreprocessStep { RegisterDepth, MetricAndIntensity, Bilateral, Pyramids, VerticesAndGradients, Normals };
inline constexpr PreprocessStep kAllPreprocessSteps[] = {
    PreprocessStep::RegisterDepth, PreprocessStep::MetricAndIntensity,   PreprocessStep::Bilateral,
    PreprocessStep::Pyramids,      PreprocessStep::VerticesAndGradients, PreprocessStep::Normals};
const char* preprocessStepName(PreprocessStep step);

/// Buffer ids of one pyramid level (device-local; valid in the arena built from the plan).
///
/// Level 0's vertices come from the UNFILTERED depth and only its normals from the filtered depth:
/// the bilateral filter rounds corners and edges differently from every viewpoint, and tracking or
/// fusing filtered points pulls the pose by several millimetres per frame even on noise-free data
/// (measured: 7 mm after one frame at 640 × 480); the raw points are unbiased and their noise
/// averages out over the image. Normals need the filter: structured-light depth is quantised into
/// plateaus whose one-pixel normals face the camera. Coarser levels are built from the filtered depth
/// and only seed the finer ones.
struct LevelBuffers {
  gpu::BufferId depth_m;    ///< filtered metric depth, float [m], 0 = invalid
  gpu::BufferId intensity;  ///< float [0..255]
  gpu::BufferId vertices;   ///< VertexPixel, camera frame [m]; level 0 from the unfiltered depth
  gpu::BufferId normals;    ///< NormalPixel, from the filtered depth
  gpu::BufferId gradients;  ///< GradientPixel [intensity / px]
};

class PreprocessStage {
 public:
  PreprocessStage(gpu::GpuContext& context, gpu::CapacityPlan& plan, const PreprocessOptions& options);
  ~PreprocessStage();

  /// Creates the kernels and writes their bindings once the arena exists.
  void build(const gpu::MemoryArena& arena);

  /// Packs one frame into the mapped upload buffers (no allocation). Sizes must match the cameras:
  /// depth options().depthCamera(), colour options().camera.
  void upload(ImageView<const std::uint16_t> depth_raw, ImageView<const Rgb8> rgb) const;

  /// Records every step, ending with a barrier that makes the outputs visible to later kernels,
  /// transfers and the host.
  void record(gpu::CommandRecorder& recorder) const;
  /// Records one step followed by a barrier (benchmarks).
  void recordStep(gpu::CommandRecorder& recorder, PreprocessStep step) const;

  const PreprocessOptions& options() const { return options_; }
  int levels() const { return options_.levels; }
  const PinholeCamera& camera(int level) const { return cameras_[level]; }
  /// Unfiltered metric depth of level 0.
  gpu::BufferId rawDepth() const { return raw_depth_m_; }
  /// Level-0 vertices of the FILTERED depth, from which the level-0 normals are computed.
  gpu::BufferId filteredVertices() const { return filtered_vertices_; }
  /// The packed RGB888 upload buffer (surfel colours are read from it).
  gpu::BufferId rgbWords() const { return rgb_words_; }
  /// Raw depth in the colour camera's pixels, packed two uint16 a word, that depth_to_metric reads:
  /// the registration's output, or the upload buffer itself when registration is skipped.
  gpu::BufferId registeredDepthWords() const { return registered_words_; }
  const LevelBuffers& level(int level) const { return levels_[level]; }

 private:
  struct Kernels;

  gpu::GpuContext& context_;
  PreprocessOptions options_;
  std::vector<PinholeCamera> cameras_;
  gpu::BufferId depth_words_;
  gpu::BufferId registration_zbuffer_;  ///< uint per colour pixel; only when registersDepth()
  gpu::BufferId registered_words_;      ///< depth_words_ unless registersDepth()
  RegisterDepthParams registration_params_;
  gpu::BufferId rgb_words_;
  gpu::BufferId raw_depth_m_;
  gpu::BufferId filtered_vertices_;
  std::vector<LevelBuffers> levels_;
  const gpu::MemoryArena* arena_ = nullptr;
  std::unique_ptr<Kernels> kernels_;
};

}  // namespace vifusion::preprocess
