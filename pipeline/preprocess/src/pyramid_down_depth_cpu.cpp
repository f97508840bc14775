// CPU reference of shaders/pyramid_down_depth.comp.

#include <cmath>

#include "view_checks.hpp"
#include "vifusion/preprocess/cpu_reference.hpp"

namespace vifusion::preprocess {

void pyramidDownDepthCpu(ImageView<const float> fine_m, const PyramidDownDepthParams& params,
                         ImageView<float> coarse_m) {
  const int dst_width = params.src_width / 2;
  const int dst_height = params.src_height / 2;
  detail::requireSize(fine_m, params.src_width, params.src_height, "pyramidDownDepthCpu", "fine_m");
  detail::requireSize(coarse_m, dst_width, dst_height, "pyramidDownDepthCpu", "coarse_m");

  for (int oy = 0; oy < dst_height; ++oy) {
    for (int ox = 0; ox < dst_width; ++ox) {
      const int x0 = 2 * ox;
      const int y0 = 2 * oy;
      const float centre_m = fine_m(x0, y0);
      if (!(centre_m > 0.0f)) {
        coarse_m(ox, oy) = 0.0f;
        continue;
      }
      float weight_sum = 0.0f;
      float weighted_depth_sum = 0.0f;
      for (int dy = -2; dy <= 2; ++dy) {
        const int y = y0 + dy;
        if (y < 0 || y >= params.src_height) continue;
        for (int dx = -2; dx <= 2; ++dx) {
          const int x = x0 + dx;
          if (x < 0 || x >= params.src_width) continue;
          const float d_m = fine_m(x, y);
          if (!(d_m > 0.0f) || std::abs(d_m - centre_m) > params.range_gate_m) continue;
          const float weight = kPyramidWeights[dx + 2] * kPyramidWeights[dy + 2];
          weight_sum += weight;
          weighted_depth_sum += weight * d_m;
        }
      }
      coarse_m(ox, oy) = weighted_depth_sum / weight_sum;
    }
  }
}

}  // namespace vifusion::preprocess
