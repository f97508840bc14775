#include "vifusion/calib/frame_signals.hpp"

#include <string>

#include "vifusion/core/error.hpp"
#include "vifusion/preprocess/cpu_reference.hpp"
#include "vifusion/preprocess/kernel_params.hpp"

namespace vifusion::calib {

void FrameSignals::assign(const RgbdFrame& frame, const RigCalibration& calibration, const DepthWindow& window) {
  const PinholeCamera& camera = calibration.camera;
  if (calibration.depth_camera) {
    throw Error(
        "noise calibration: depth from its own camera (cam1 in the calibration) is not supported; it needs "
        "depth in the colour camera's pixels, as datasets and the simulator give it");
  }
  const auto size_text = [](int w, int h) { return std::to_string(w) + "×" + std::to_string(h); };
  if (frame.depth.width() != camera.width || frame.depth.height() != camera.height ||
      frame.rgb.width() != camera.width || frame.rgb.height() != camera.height) {
    throw Error("noise calibration: frame " + std::to_string(frame.index) + " has depth " +
                size_text(frame.depth.width(), frame.depth.height()) + " and colour " +
                size_text(frame.rgb.width(), frame.rgb.height()) + ", the calibration's camera is " +
                size_text(camera.width, camera.height));
  }
  if (inverse_depth_per_m.width() != camera.width || inverse_depth_per_m.height() != camera.height) {
    inverse_depth_per_m.resize(camera.width, camera.height);
    grey.resize(camera.width, camera.height);
    depth_m_.resize(camera.width, camera.height);
  }

  preprocess::DepthToMetricParams metric;
  metric.width = camera.width;
  metric.height = camera.height;
  metric.depth_scale_m =
      static_cast<float>(frame.depth_scale_m > 0.0 ? frame.depth_scale_m : calibration.depth_scale_m);
  metric.min_depth_m = static_cast<float>(window.min_depth_m);
  metric.max_depth_m = static_cast<float>(window.max_depth_m);
  metric.inverse_depth_bias_per_m = static_cast<float>(calibration.inverse_depth_bias_per_m);
  preprocess::depthToMetricCpu(frame.depth.view(), metric, depth_m_.view());
  for (std::size_t i = 0; i < depth_m_.pixelCount(); ++i) {
    const float z_m = depth_m_.data()[i];
    inverse_depth_per_m.data()[i] = z_m > 0.0F ? 1.0F / z_m : 0.0F;
  }

  preprocess::RgbToIntensityParams intensity;
  intensity.width = camera.width;
  intensity.height = camera.height;
  preprocess::rgbToIntensityCpu(frame.rgb.view(), intensity, grey.view());
}

}  // namespace vifusion::calib
