#include "vifusion/tracking/photometric_params.hpp"

#include <cmath>
#include <string>

#include "pose_and_camera.hpp"
#include "vifusion/core/error.hpp"

namespace vifusion::tracking {

void PhotometricOptions::validate() const {
  const auto positive = [](float value, const char* name) {
    if (!(value > 0.0f) || !std::isfinite(value)) {
      throw Error(std::string("photometric option '") + name + "' = " + std::to_string(value) +
                  " must be finite and > 0");
    }
  };
  positive(sigma_intensity, "sigma_intensity");
  positive(huber_k, "huber_k");
  positive(max_depth_difference_m, "max_depth_difference_m");
  if (!(min_gradient >= 0.0f)) throw Error("photometric option 'min_gradient' must be ≥ 0");
  if (!(sigma_position_px >= 0.0f && sigma_position_px <= 2.0f)) {
    throw Error("photometric option 'sigma_position_px' must be in [0, 2]");
  }
}

PhotometricParams PhotometricParams::make(const SE3d& T_ref_cur, const PinholeCamera& camera,
                                          const PhotometricOptions& options, int level, bool use_reference_fill) {
  PhotometricParams params;
  setPoseAndCamera(params, T_ref_cur, camera);
  params.sigma_intensity = options.sigma_intensity;
  params.huber_k = options.huber_k;
  params.min_gradient = options.min_gradient;
  params.max_depth_difference_m = options.max_depth_difference_m;
  params.sigma_position_px = options.sigma_position_px;
  params.support_radius_px = level > 0 ? 3 : 2;
  params.use_reference_fill = use_reference_fill ? 1 : 0;
  return params;
}

}  // namespace vifusion::tracking
