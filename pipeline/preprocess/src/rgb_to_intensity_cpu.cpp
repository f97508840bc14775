// CPU reference of shaders/rgb_to_intensity.comp.

#include "view_checks.hpp"
#include "vifusion/preprocess/cpu_reference.hpp"

namespace vifusion::preprocess {

void rgbToIntensityCpu(ImageView<const Rgb8> rgb, const RgbToIntensityParams& params, ImageView<float> intensity) {
  detail::requireSize(rgb, params.width, params.height, "rgbToIntensityCpu", "rgb");
  detail::requireSize(intensity, params.width, params.height, "rgbToIntensityCpu", "intensity");
  for (int y = 0; y < params.height; ++y) {
    for (int x = 0; x < params.width; ++x) {
      const Rgb8 pixel = rgb(x, y);
      const float r = static_cast<float>(pixel.r);
      const float g = static_cast<float>(pixel.g);
      const float b = static_cast<float>(pixel.b);
      intensity(x, y) = params.weight_r * r + params.weight_g * g + params.weight_b * b;
    }
  }
}

}  // namespace vifusion::preprocess
