#include "vifusion/tracking/icp_params.hpp"

#include <string>

#include "pose_and_camera.hpp"
#include "vifusion/core/error.hpp"

namespace vifusion::tracking {

void IcpOptions::validate() const {
  const auto positive = [](float value, const char* name) {
    if (!(value > 0.0f) || !std::isfinite(value)) {
      throw Error(std::string("ICP option '") + name + "' = " + std::to_string(value) + " must be finite and > 0");
    }
  };
  positive(max_distance_m, "max_distance_m");
  positive(max_normal_angle_rad, "max_normal_angle_rad");
  positive(sigma_z_a_m, "sigma_z_a_m");
  positive(huber_k, "huber_k");
  if (!(sigma_z_b_per_m >= 0.0f)) throw Error("ICP option 'sigma_z_b_per_m' must be ≥ 0");
  if (!(inverse_depth_bias_sigma_per_m >= 0.0f) || !std::isfinite(inverse_depth_bias_sigma_per_m)) {
    throw Error("ICP option 'inverse_depth_bias_sigma_per_m' must be finite and ≥ 0");
  }
  if (max_normal_angle_rad >= 1.5707963f) throw Error("ICP option 'max_normal_angle_rad' must be below π/2");
}

IcpParams IcpParams::make(const SE3d& T_ref_cur, const PinholeCamera& camera, const IcpOptions& options) {
  IcpParams params;
  setPoseAndCamera(params, T_ref_cur, camera);
  params.max_distance_m = options.max_distance_m;
  params.max_normal_sin = std::sin(options.max_normal_angle_rad);
  params.sigma_z_a_m = options.sigma_z_a_m;
  params.sigma_z_b_per_m = options.sigma_z_b_per_m;
  params.sigma_z_z0_m = options.sigma_z_z0_m;
  params.huber_k = options.huber_k;
  params.inverse_depth_bias_sigma_per_m = options.inverse_depth_bias_sigma_per_m;
  return params;
}

}  // namespace vifusion::tracking
