// CPU reference of shaders/intensity_gradient.comp.

#include <algorithm>

#include "view_checks.hpp"
#include "vifusion/preprocess/cpu_reference.hpp"

namespace vifusion::preprocess {

void intensityGradientCpu(ImageView<const float> intensity, const IntensityGradientParams& params,
                          ImageView<GradientPixel> gradient) {
  detail::requireSize(intensity, params.width, params.height, "intensityGradientCpu", "intensity");
  detail::requireSize(gradient, params.width, params.height, "intensityGradientCpu", "gradient");
  for (int y = 0; y < params.height; ++y) {
    const int ym = std::max(y - 1, 0);
    const int yp = std::min(y + 1, params.height - 1);
    for (int x = 0; x < params.width; ++x) {
      const int xm = std::max(x - 1, 0);
      const int xp = std::min(x + 1, params.width - 1);
      const float right = intensity(xp, ym) + 2.0f * intensity(xp, y) + intensity(xp, yp);
      const float left = intensity(xm, ym) + 2.0f * intensity(xm, y) + intensity(xm, yp);
      const float below = intensity(xm, yp) + 2.0f * intensity(x, yp) + intensity(xp, yp);
      const float above = intensity(xm, ym) + 2.0f * intensity(x, ym) + intensity(xp, ym);
      gradient(x, y) = GradientPixel((right - left) * 0.125f, (below - above) * 0.125f);
    }
  }
}

}  // namespace vifusion::preprocess
