#include "vifusion/preprocess/preprocess_cpu.hpp"

#include "vifusion/core/error.hpp"
#include "vifusion/preprocess/cpu_reference.hpp"

namespace vifusion::preprocess {

PreprocessCpu::PreprocessCpu(const PreprocessOptions& options) : options_(options) {
  options_.validate();
  const PinholeCamera& camera = options_.camera;
  options_.metric.width = options_.bilateral.width = options_.intensity.width = camera.width;
  options_.metric.height = options_.bilateral.height = options_.intensity.height = camera.height;
  if (options_.registersDepth()) {
    registration_params_ = options_.registration->kernelParams();
    registered_raw_.resize(camera.width, camera.height);
  }
  raw_depth_m_.resize(camera.width, camera.height);
  filtered_vertices_ = Image<VertexPixel>(camera.width, camera.height, VertexPixel::Zero());
  for (int l = 0; l < options_.levels; ++l) {
    const PinholeCamera level_camera = camera.atLevel(l);
    cameras_.push_back(level_camera);
    const int w = level_camera.width;
    const int h = level_camera.height;
    levels_.push_back({Image<float>(w, h), Image<float>(w, h), Image<VertexPixel>(w, h, VertexPixel::Zero()),
                       Image<NormalPixel>(w, h, NormalPixel::Zero()),
                       Image<GradientPixel>(w, h, GradientPixel::Zero())});
  }
}

void PreprocessCpu::setInput(ImageView<const std::uint16_t> depth_raw, ImageView<const Rgb8> rgb) {
  const PinholeCamera& depth_camera = options_.depthCamera();
  if (depth_raw.width != depth_camera.width || depth_raw.height != depth_camera.height ||
      rgb.width != options_.camera.width || rgb.height != options_.camera.height) {
    throw Error("preprocess (CPU): frame size does not match the cameras");
  }
  depth_raw_ = depth_raw;
  rgb_ = rgb;
}

void PreprocessCpu::runStep(PreprocessStep step) {
  switch (step) {
    case PreprocessStep::RegisterDepth:
      if (options_.registersDepth()) registerDepthCpu(depth_raw_, registration_params_, registered_raw_.view());
      break;
    case PreprocessStep::MetricAndIntensity:
      depthToMetricCpu(options_.registersDepth() ? ImageView<const std::uint16_t>(registered_raw_.view()) : depth_raw_,
                       options_.metric, raw_depth_m_.view());
      rgbToIntensityCpu(rgb_, options_.intensity, levels_[0].intensity.view());
      break;
    case PreprocessStep::Bilateral:
      bilateralDepthCpu(raw_depth_m_.view(), options_.bilateral, levels_[0].depth_m.view());
      break;
    case PreprocessStep::Pyramids:
      for (int l = 1; l < options_.levels; ++l) {
        const PinholeCamera& fine = cameras_[l - 1];
        pyramidDownDepthCpu(levels_[l - 1].depth_m.view(), {fine.width, fine.height, options_.pyramid_range_gate_m},
                            levels_[l].depth_m.view());
        pyramidDownIntensityCpu(levels_[l - 1].intensity.view(), {fine.width, fine.height},
                                levels_[l].intensity.view());
      }
      break;
    case PreprocessStep::VerticesAndGradients:
      vertexMapCpu(levels_[0].depth_m.view(), VertexMapParams::fromCamera(cameras_[0]), filtered_vertices_.view());
      for (int l = 0; l < options_.levels; ++l) {
        const Image<float>& depth_m = l == 0 ? raw_depth_m_ : levels_[l].depth_m;
        vertexMapCpu(depth_m.view(), VertexMapParams::fromCamera(cameras_[l]), levels_[l].vertices.view());
        intensityGradientCpu(levels_[l].intensity.view(), {cameras_[l].width, cameras_[l].height},
                             levels_[l].gradients.view());
      }
      break;
    case PreprocessStep::Normals:
      for (int l = 0; l < options_.levels; ++l) {
        const Image<VertexPixel>& vertices = l == 0 ? filtered_vertices_ : levels_[l].vertices;
        normalMapCpu(vertices.view(), options_.normalParams(cameras_[l]), levels_[l].normals.view());
      }
      break;
  }
}

void PreprocessCpu::run() {
  for (PreprocessStep step : kAllPreprocessSteps) runStep(step);
}

}  // namespace vifusion::preprocess
