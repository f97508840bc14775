// CPU reference of shaders/pyramid_down_intensity.comp.

#include <algorithm>

#include "view_checks.hpp"
#include "vifusion/preprocess/cpu_reference.hpp"

namespace vifusion::preprocess {

void pyramidDownIntensityCpu(ImageView<const float> fine, const PyramidDownIntensityParams& params,
                             ImageView<float> coarse) {
  const int dst_width = params.src_width / 2;
  const int dst_height = params.src_height / 2;
  detail::requireSize(fine, params.src_width, params.src_height, "pyramidDownIntensityCpu", "fine");
  detail::requireSize(coarse, dst_width, dst_height, "pyramidDownIntensityCpu", "coarse");

  for (int oy = 0; oy < dst_height; ++oy) {
    for (int ox = 0; ox < dst_width; ++ox) {
      float sum = 0.0f;
      for (int dy = -2; dy <= 2; ++dy) {
        const int y = std::clamp(2 * oy + dy, 0, params.src_height - 1);
        for (int dx = -2; dx <= 2; ++dx) {
          const int x = std::clamp(2 * ox + dx, 0, params.src_width - 1);
          sum += (kPyramidWeights[dx + 2] * kPyramidWeights[dy + 2]) * fine(x, y);
        }
      }
      coarse(ox, oy) = sum;
    }
  }
}

}  // namespace vifusion::preprocess
