#include "vifusion/preprocess/preprocess_stage.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "vifusion/core/error.hpp"
#include "vifusion/core/rig_calibration.hpp"
#include "vifusion/preprocess/packing.hpp"
#include "vifusion/shaders/spirv.hpp"

namespace vifusion::preprocess {
namespace {

/// The scatter pass's empty z-buffer entry (kEmptyZ in register_depth.comp): above every depth.
constexpr uint32_t kEmptyDepthZ = 0xFFFFFFFFu;

std::string field(const char* name) { return std::string("preprocess option '") + name + "'"; }

uint64_t pixels(const PinholeCamera& camera) { return uint64_t(camera.width) * uint64_t(camera.height); }

bool sameCamera(const PinholeCamera& a, const PinholeCamera& b) {
  return a.width == b.width && a.height == b.height && a.fx == b.fx && a.fy == b.fy && a.cx == b.cx && a.cy == b.cy;
}

/// The registration's own checks, then that it describes the same colour camera and depth units as
/// the rest of the options (the stage keeps one of each).
void validateRegistration(const PreprocessOptions& options) {
  const DepthRegistration& registration = *options.registration;
  registration.validate();
  if (!sameCamera(registration.colour, options.camera)) {
    throw Error(field("registration.colour") + " differs from 'camera': depth is registered to the colour camera");
  }
  if (static_cast<float>(registration.depth_scale_m) != options.metric.depth_scale_m) {
    throw Error(field("registration.depth_scale_m") + " (" + std::to_string(registration.depth_scale_m) +
                ") differs from 'metric.depth_scale_m' (" + std::to_string(options.metric.depth_scale_m) + ")");
  }
  if (registration.depth.width % 2 != 0) {
    throw Error(field("registration.depth") + ": width " + std::to_string(registration.depth.width) +
                " is odd (depth is packed 2 pixels a word)");
  }
}

}  // namespace

void PreprocessOptions::validate() const {
  if (camera.width <= 0 || camera.height <= 0) throw Error(field("camera") + ": image size is not set");
  if (camera.width % 2 != 0) {
    throw Error(field("camera") + ": width " + std::to_string(camera.width) +
                " is odd (depth is packed 2 pixels a word)");
  }
  if (levels < 1 || (camera.width >> (levels - 1)) < 8 || (camera.height >> (levels - 1)) < 8) {
    throw Error(field("levels") + ": " + std::to_string(levels) +
                " levels leave fewer than 8 px at the coarsest level of " + std::to_string(camera.width) + "x" +
                std::to_string(camera.height));
  }
  if (!(metric.depth_scale_m > 0.0f)) throw Error(field("metric.depth_scale_m") + " must be > 0");
  static_assert(kMaxInverseDepthBias_per_m == 0.1, "the message below quotes the bound");
  if (!(std::abs(metric.inverse_depth_bias_per_m) <= kMaxInverseDepthBias_per_m)) {
    throw Error(field("metric.inverse_depth_bias_per_m") + " must be within ±0.1 1/m, got " +
                std::to_string(metric.inverse_depth_bias_per_m));
  }
  if (!(metric.min_depth_m >= 0.0f) || !(metric.min_depth_m < metric.max_depth_m)) {
    throw Error(field("metric") + ": need 0 ≤ min_depth_m < max_depth_m, got " + std::to_string(metric.min_depth_m) +
                " and " + std::to_string(metric.max_depth_m));
  }
  if (bilateral.radius_px < 0 || bilateral.radius_px > 15)
    throw Error(field("bilateral.radius_px") + " must be in 0..15");
  if (!(bilateral.sigma_space_px > 0.0f)) throw Error(field("bilateral.sigma_space_px") + " must be > 0");
  if (!(bilateral.range_sigmas > 0.0f)) throw Error(field("bilateral.range_sigmas") + " must be > 0");
  if (!(bilateral.noise_a_m > 0.0f)) throw Error(field("bilateral.noise_a_m") + " must be > 0");
  if (!(bilateral.noise_b_per_m >= 0.0f)) throw Error(field("bilateral.noise_b_per_m") + " must be ≥ 0");
  if (!(pyramid_range_gate_m > 0.0f)) throw Error(field("pyramid_range_gate_m") + " must be > 0");
  if (!(normals.min_cross_norm_m2 >= 1e-18f)) throw Error(field("normals.min_cross_norm_m2") + " must be ≥ 1e-18");
  if (!(normal_span_rad > 0.0f && normal_span_rad < 0.1f))
    throw Error(field("normal_span_rad") + " must be in (0, 0.1)");
  if (workgroup_size == 0 || workgroup_size > 32) throw Error(field("workgroup_size") + " must be in 1..32");
  if (registration) validateRegistration(*this);
}

NormalMapParams PreprocessOptions::normalParams(const PinholeCamera& level_camera) const {
  NormalMapParams params = normals;
  params.width = level_camera.width;
  params.height = level_camera.height;
  params.span_px = std::max(1, static_cast<int>(std::lround(normal_span_rad * level_camera.fx)));
  return params;
}

const char* preprocessStepName(PreprocessStep step) {
  switch (step) {
    case PreprocessStep::RegisterDepth:
      return "register_depth";
    case PreprocessStep::MetricAndIntensity:
      return "metric_and_intensity";
    case PreprocessStep::Bilateral:
      return "bilateral";
    case PreprocessStep::Pyramids:
      return "pyramids";
    case PreprocessStep::VerticesAndGradients:
      return "vertices_and_gradients";
    case PreprocessStep::Normals:
      return "normals";
  }
  return "?";
}

/// One kernel per shader; kernels used at several levels hold one binding set per level.
struct PreprocessStage::Kernels {
  std::unique_ptr<gpu::ComputeKernel> register_scatter, register_resolve;  ///< only when registersDepth()
  std::unique_ptr<gpu::ComputeKernel> metric, intensity, bilateral, pyramid_depth, pyramid_intensity, vertices, normals,
      gradients;
  gpu::BindingSet register_scatter_set, register_resolve_set;
  gpu::BindingSet metric_set, intensity_set, bilateral_set, filtered_vertex_set;
  std::vector<gpu::BindingSet> pyramid_depth_sets, pyramid_intensity_sets, vertex_sets, normal_sets, gradient_sets;
};

PreprocessStage::PreprocessStage(gpu::GpuContext& context, gpu::CapacityPlan& plan, const PreprocessOptions& options)
    : context_(context), options_(options) {
  options_.validate();
  const PinholeCamera& camera = options_.camera;
  options_.metric.width = options_.bilateral.width = options_.intensity.width = camera.width;
  options_.metric.height = options_.bilateral.height = options_.intensity.height = camera.height;

  const PinholeCamera& depth_camera = options_.depthCamera();
  depth_words_ =
      plan.addBuffer("preprocess.depth_raw", packedDepthWordCount(depth_camera.width, depth_camera.height) * 4,
                     gpu::MemoryUse::Upload);
  registered_words_ = depth_words_;
  if (options_.registersDepth()) {
    registration_params_ = options_.registration->kernelParams();
    registration_zbuffer_ = plan.addBuffer("preprocess.registration_zbuffer", pixels(camera) * sizeof(uint32_t),
                                           gpu::MemoryUse::DeviceLocal);
    registered_words_ =
        plan.addBuffer("preprocess.depth_registered", packedDepthWordCount(camera.width, camera.height) * 4,
                       gpu::MemoryUse::DeviceLocal);
  }
  rgb_words_ =
      plan.addBuffer("preprocess.rgb", packedRgbWordCount(camera.width, camera.height) * 4, gpu::MemoryUse::Upload);
  raw_depth_m_ = plan.addBuffer("preprocess.depth_metric", pixels(camera) * sizeof(float), gpu::MemoryUse::DeviceLocal);
  filtered_vertices_ =
      plan.addBuffer("preprocess.vertices_filtered", pixels(camera) * sizeof(VertexPixel), gpu::MemoryUse::DeviceLocal);
  for (int l = 0; l < options_.levels; ++l) {
    cameras_.push_back(camera.atLevel(l));
    const uint64_t n = pixels(cameras_.back());
    const std::string prefix = "preprocess.l" + std::to_string(l) + ".";
    levels_.push_back({plan.addBuffer(prefix + "depth", n * sizeof(float), gpu::MemoryUse::DeviceLocal),
                       plan.addBuffer(prefix + "intensity", n * sizeof(float), gpu::MemoryUse::DeviceLocal),
                       plan.addBuffer(prefix + "vertices", n * sizeof(VertexPixel), gpu::MemoryUse::DeviceLocal),
                       plan.addBuffer(prefix + "normals", n * sizeof(NormalPixel), gpu::MemoryUse::DeviceLocal),
                       plan.addBuffer(prefix + "gradients", n * sizeof(GradientPixel), gpu::MemoryUse::DeviceLocal)});
  }
}

PreprocessStage::~PreprocessStage() = default;

void PreprocessStage::build(const gpu::MemoryArena& arena) {
  arena_ = &arena;
  kernels_ = std::make_unique<Kernels>();
  Kernels& k = *kernels_;
  const uint32_t levels = static_cast<uint32_t>(options_.levels);
  auto make = [&](const char* name, std::span<const uint32_t> spirv, uint32_t buffers, uint32_t push_bytes,
                  uint32_t sets) {
    gpu::KernelSpec spec;
    spec.name = name;
    spec.spirv = spirv;
    spec.storage_buffers = buffers;
    spec.push_constant_bytes = push_bytes;
    spec.workgroup_size = {options_.workgroup_size, options_.workgroup_size, 1};
    spec.max_binding_sets = sets;
    return gpu::ComputeKernel::create(context_, std::move(spec));
  };
  const uint32_t pyramid_sets = levels > 1 ? levels - 1 : 1;
  auto buffer = [&](gpu::BufferId id) { return &arena.buffer(id); };
  if (options_.registersDepth()) {
    k.register_scatter =
        make("register_depth_scatter", shaders::register_depth_scatter, 2, sizeof(RegisterDepthParams), 1);
    k.register_resolve =
        make("register_depth_resolve", shaders::register_depth_resolve, 2, sizeof(RegisterDepthParams), 1);
    k.register_scatter_set = k.register_scatter->bind({buffer(depth_words_), buffer(registration_zbuffer_)});
    k.register_resolve_set = k.register_resolve->bind({buffer(registration_zbuffer_), buffer(registered_words_)});
  }
  k.metric = make("depth_to_metric", shaders::depth_to_metric, 2, sizeof(DepthToMetricParams), 1);
  k.intensity = make("rgb_to_intensity", shaders::rgb_to_intensity, 2, sizeof(RgbToIntensityParams), 1);
  k.bilateral = make("bilateral_depth", shaders::bilateral_depth, 2, sizeof(BilateralDepthParams), 1);
  k.pyramid_depth =
      make("pyramid_down_depth", shaders::pyramid_down_depth, 2, sizeof(PyramidDownDepthParams), pyramid_sets);
  k.pyramid_intensity = make("pyramid_down_intensity", shaders::pyramid_down_intensity, 2,
                             sizeof(PyramidDownIntensityParams), pyramid_sets);
  k.vertices = make("vertex_map", shaders::vertex_map, 2, sizeof(VertexMapParams), levels + 1);
  k.normals = make("normal_map", shaders::normal_map, 2, sizeof(NormalMapParams), levels);
  k.gradients = make("intensity_gradient", shaders::intensity_gradient, 2, sizeof(IntensityGradientParams), levels);

  k.metric_set = k.metric->bind({buffer(registered_words_), buffer(raw_depth_m_)});
  k.intensity_set = k.intensity->bind({buffer(rgb_words_), buffer(levels_[0].intensity)});
  k.bilateral_set = k.bilateral->bind({buffer(raw_depth_m_), buffer(levels_[0].depth_m)});
  k.filtered_vertex_set = k.vertices->bind({buffer(levels_[0].depth_m), buffer(filtered_vertices_)});
  for (uint32_t l = 0; l < levels; ++l) {
    const LevelBuffers& level = levels_[l];
    if (l > 0) {
      k.pyramid_depth_sets.push_back(k.pyramid_depth->bind({buffer(levels_[l - 1].depth_m), buffer(level.depth_m)}));
      k.pyramid_intensity_sets.push_back(
          k.pyramid_intensity->bind({buffer(levels_[l - 1].intensity), buffer(level.intensity)}));
    }
    k.vertex_sets.push_back(k.vertices->bind({buffer(l == 0 ? raw_depth_m_ : level.depth_m), buffer(level.vertices)}));
    k.normal_sets.push_back(
        k.normals->bind({buffer(l == 0 ? filtered_vertices_ : level.vertices), buffer(level.normals)}));
    k.gradient_sets.push_back(k.gradients->bind({buffer(level.intensity), buffer(level.gradients)}));
  }
}

void PreprocessStage::upload(ImageView<const std::uint16_t> depth_raw, ImageView<const Rgb8> rgb) const {
  const PinholeCamera& camera = options_.camera;
  const PinholeCamera& depth_camera = options_.depthCamera();
  if (depth_raw.width != depth_camera.width || depth_raw.height != depth_camera.height || rgb.width != camera.width ||
      rgb.height != camera.height) {
    throw Error("preprocess: frame of " + std::to_string(depth_raw.width) + "x" + std::to_string(depth_raw.height) +
                " depth and " + std::to_string(rgb.width) + "x" + std::to_string(rgb.height) + " colour, cameras are " +
                std::to_string(depth_camera.width) + "x" + std::to_string(depth_camera.height) + " (depth) and " +
                std::to_string(camera.width) + "x" + std::to_string(camera.height) + " (colour)");
  }
  packDepth(depth_raw, arena_->buffer(depth_words_).hostSpan<std::uint32_t>());
  packRgb(rgb, arena_->buffer(rgb_words_).hostSpan<std::uint32_t>());
}

void PreprocessStage::record(gpu::CommandRecorder& recorder) const {
  for (PreprocessStep step : kAllPreprocessSteps) recordStep(recorder, step);
  recorder.hostReadBarrier();
}

void PreprocessStage::recordStep(gpu::CommandRecorder& recorder, PreprocessStep step) const {
  const Kernels& k = *kernels_;
  const auto groups = [&](const gpu::ComputeKernel& kernel, int level) {
    return kernel.groupsFor(static_cast<uint32_t>(cameras_[level].width),
                            static_cast<uint32_t>(cameras_[level].height));
  };
  switch (step) {
    case PreprocessStep::RegisterDepth:
      if (!options_.registersDepth()) return;  // nothing to record, not even a barrier
      recorder.fillBuffer(arena_->buffer(registration_zbuffer_), kEmptyDepthZ);
      recorder.computeBarrier();
      recorder.dispatch(*k.register_scatter, k.register_scatter_set,
                        k.register_scatter->groupsFor(static_cast<uint32_t>(registration_params_.depth_width),
                                                      static_cast<uint32_t>(registration_params_.depth_height)),
                        registration_params_);
      recorder.computeBarrier();
      // One invocation per packed word: two colour pixels of a row.
      recorder.dispatch(*k.register_resolve, k.register_resolve_set,
                        k.register_resolve->groupsFor(static_cast<uint32_t>(cameras_[0].width / 2),
                                                      static_cast<uint32_t>(cameras_[0].height)),
                        registration_params_);
      break;
    case PreprocessStep::MetricAndIntensity:
      recorder.dispatch(*k.metric, k.metric_set, groups(*k.metric, 0), options_.metric);
      recorder.dispatch(*k.intensity, k.intensity_set, groups(*k.intensity, 0), options_.intensity);
      break;
    case PreprocessStep::Bilateral:
      // Off (radius 0, the default) the filter is the identity: a buffer copy instead of a kernel,
      // which on lavapipe costs ~1/40 of a pass that reads and writes every pixel lane by lane.
      if (options_.bilateral.radius_px == 0) {
        recorder.copyBuffer(arena_->buffer(raw_depth_m_), arena_->buffer(levels_[0].depth_m),
                            arena_->buffer(raw_depth_m_).bytes);
      } else {
        recorder.dispatch(*k.bilateral, k.bilateral_set, groups(*k.bilateral, 0), options_.bilateral);
      }
      break;
    case PreprocessStep::Pyramids:
      // Level l needs level l−1, so each level is its own barrier-separated pass.
      for (int l = 1; l < options_.levels; ++l) {
        const PyramidDownDepthParams depth{cameras_[l - 1].width, cameras_[l - 1].height,
                                           options_.pyramid_range_gate_m};
        const PyramidDownIntensityParams intensity{cameras_[l - 1].width, cameras_[l - 1].height};
        recorder.dispatch(*k.pyramid_depth, k.pyramid_depth_sets[l - 1], groups(*k.pyramid_depth, l), depth);
        recorder.dispatch(*k.pyramid_intensity, k.pyramid_intensity_sets[l - 1], groups(*k.pyramid_intensity, l),
                          intensity);
        if (l + 1 < options_.levels) recorder.computeBarrier();
      }
      break;
    case PreprocessStep::VerticesAndGradients:
      if (options_.bilateral.radius_px != 0) {
        recorder.dispatch(*k.vertices, k.filtered_vertex_set, groups(*k.vertices, 0),
                          VertexMapParams::fromCamera(cameras_[0]));
      }
      for (int l = 0; l < options_.levels; ++l) {
        recorder.dispatch(*k.vertices, k.vertex_sets[l], groups(*k.vertices, l),
                          VertexMapParams::fromCamera(cameras_[l]));
        const IntensityGradientParams gradient{cameras_[l].width, cameras_[l].height};
        recorder.dispatch(*k.gradients, k.gradient_sets[l], groups(*k.gradients, l), gradient);
      }
      if (options_.bilateral.radius_px == 0) {
        // Filter off: the filtered depth is a copy of the raw depth, so are its vertices.
        recorder.computeBarrier();
        recorder.copyBuffer(arena_->buffer(levels_[0].vertices), arena_->buffer(filtered_vertices_),
                            arena_->buffer(filtered_vertices_).bytes);
      }
      break;
    case PreprocessStep::Normals:
      for (int l = 0; l < options_.levels; ++l) {
        recorder.dispatch(*k.normals, k.normal_sets[l], groups(*k.normals, l), options_.normalParams(cameras_[l]));
      }
      break;
  }
  recorder.computeBarrier();
}

}  // namespace vifusion::preprocess
