// CPU reference of shaders/depth_to_metric.comp.

#include "view_checks.hpp"
#include "vifusion/preprocess/cpu_reference.hpp"

namespace vifusion::preprocess {

void depthToMetricCpu(ImageView<const std::uint16_t> raw, const DepthToMetricParams& params,
                      ImageView<float> depth_m) {
  detail::requireSize(raw, params.width, params.height, "depthToMetricCpu", "raw");
  detail::requireSize(depth_m, params.width, params.height, "depthToMetricCpu", "depth_m");
  for (int y = 0; y < params.height; ++y) {
    for (int x = 0; x < params.width; ++x) {
      const std::uint16_t value = raw(x, y);
      const float z_raw_m = static_cast<float>(value) * params.depth_scale_m;
      const float denominator = 1.0f - params.inverse_depth_bias_per_m * z_raw_m;
      const float z_m = z_raw_m / denominator;
      const bool valid = value != 0 && denominator > 0.0f && z_m >= params.min_depth_m && z_m <= params.max_depth_m;
      depth_m(x, y) = valid ? z_m : 0.0f;
    }
  }
}

}  // namespace vifusion::preprocess
