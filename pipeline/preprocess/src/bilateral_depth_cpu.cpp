// CPU reference of shaders/bilateral_depth.comp. Same loop order (rows outer, columns inner) and
// the same float expressions, so the sums accumulate identically; only exp and the final division
// may differ by a few ULP from the GPU's. Radius 0 (off) is the identity, which PreprocessStage
// records as a buffer copy rather than the kernel (whose 1/(1/z) would differ from z by an ulp).

#include <cmath>
#include <stdexcept>

#include "view_checks.hpp"
#include "vifusion/preprocess/cpu_reference.hpp"

namespace vifusion::preprocess {

void bilateralDepthCpu(ImageView<const float> depth_m, const BilateralDepthParams& params,
                       ImageView<float> filtered_m) {
  detail::requireSize(depth_m, params.width, params.height, "bilateralDepthCpu", "depth_m");
  detail::requireSize(filtered_m, params.width, params.height, "bilateralDepthCpu", "filtered_m");
  if (static_cast<const void*>(depth_m.data) == static_cast<const void*>(filtered_m.data)) {
    throw std::invalid_argument("bilateralDepthCpu: input and output must not alias");
  }

  const int r = params.radius_px;
  if (r == 0) {  // off: the identity, as PreprocessStage records it (a copy, invalid depth stays 0)
    for (int y0 = 0; y0 < params.height; ++y0) {
      for (int x0 = 0; x0 < params.width; ++x0) filtered_m(x0, y0) = depth_m(x0, y0) > 0.0f ? depth_m(x0, y0) : 0.0f;
    }
    return;
  }
  const float space_coeff = 0.5f / (params.sigma_space_px * params.sigma_space_px);  // 1/(2σ_s²) [1/px²]
  for (int y0 = 0; y0 < params.height; ++y0) {
    for (int x0 = 0; x0 < params.width; ++x0) {
      const float centre_m = depth_m(x0, y0);
      if (!(centre_m > 0.0f)) {
        filtered_m(x0, y0) = 0.0f;
        continue;
      }
      const float dz_m = centre_m - params.noise_z0_m;
      const float sigma_range_m = params.range_sigmas * (params.noise_a_m + params.noise_b_per_m * dz_m * dz_m);
      const float range_coeff = 0.5f / (sigma_range_m * sigma_range_m);  // 1/(2σ_r²) [1/m²]
      const float inverse_centre = 1.0f / centre_m;
      float weight_sum = 0.0f;
      float weighted_inverse_sum = 0.0f;
      for (int dy = -r; dy <= r; ++dy) {
        const int y = y0 + dy;
        if (y < 0 || y >= params.height) continue;
        for (int dx = -r; dx <= r; ++dx) {
          const int x = x0 + dx;
          if (x < 0 || x >= params.width) continue;
          const float d_m = depth_m(x, y);
          if (!(d_m > 0.0f)) continue;
          const float inverse_d = 1.0f / d_m;
          const float diff_m = centre_m * centre_m * (inverse_d - inverse_centre);
          const float weight =
              std::exp(-(static_cast<float>(dx * dx + dy * dy) * space_coeff) - (diff_m * diff_m) * range_coeff);
          weight_sum += weight;
          weighted_inverse_sum += weight * inverse_d;
        }
      }
      filtered_m(x0, y0) = weight_sum / weighted_inverse_sum;
    }
  }
}

}  // namespace vifusion::preprocess
