#include "vifusion/map/fusion_params.hpp"

#include <cmath>
#include <string>

#include "vifusion/core/error.hpp"

namespace vifusion::map {
namespace {

void copyRows(const SE3d& T, float (&rows)[3][4]) {
  const Eigen::Matrix4d M = T.matrix();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) rows[r][c] = static_cast<float>(M(r, c));
  }
}

}  // namespace

void FusionOptions::validate() const {
  const auto positive = [](float value, const char* name) {
    if (!(value > 0.0f) || !std::isfinite(value)) {
      throw Error(std::string("fusion option '") + name + "' = " + std::to_string(value) + " must be finite and > 0");
    }
  };
  positive(max_depth_diff_m, "max_depth_diff_m");
  positive(max_normal_angle_rad, "max_normal_angle_rad");
  positive(confidence_sigma, "confidence_sigma");
  positive(radius_update_ratio, "radius_update_ratio");
  if (max_normal_angle_rad >= 1.5707963f) throw Error("fusion option 'max_normal_angle_rad' must be below π/2");
  if (!(grazing_normal_z >= 0.0f && grazing_normal_z <= 1.0f)) {
    throw Error("fusion option 'grazing_normal_z' must be in 0..1");
  }
  if (!(depth_noise.a_m >= 0.0f && depth_noise.b_per_m >= 0.0f && std::isfinite(depth_noise.z0_m))) {
    throw Error("fusion option 'depth_noise' must have a, b ≥ 0 and a finite z0");
  }
}

FusionParams FusionParams::make(const SE3d& T_W_C, std::uint32_t frame, const PinholeCamera& camera,
                                const MapOptions& map, const FusionOptions& fusion,
                                const FusionPoseUncertainty& uncertainty) {
  if (!(uncertainty.position_variance_m2 >= 0.0) || !(uncertainty.rotation_variance_rad2 >= 0.0)) {
    throw Error("fusion pose variances must be ≥ 0 (got " + std::to_string(uncertainty.position_variance_m2) + " m², " +
                std::to_string(uncertainty.rotation_variance_rad2) + " rad²)");
  }
  FusionParams params;
  copyRows(T_W_C.inverse(), params.T_C_W_rows);
  copyRows(T_W_C, params.T_W_C_rows);
  params.fx = static_cast<float>(camera.fx);
  params.fy = static_cast<float>(camera.fy);
  params.cx = static_cast<float>(camera.cx);
  params.cy = static_cast<float>(camera.cy);
  params.width = camera.width;
  params.height = camera.height;
  params.frame = frame;
  params.time_window_frames = map.time_window_frames;
  params.max_depth_m = map.max_depth_m;
  params.max_depth_diff_m = fusion.max_depth_diff_m;
  params.min_normal_cos = std::cos(fusion.max_normal_angle_rad);
  params.grazing_normal_z = fusion.grazing_normal_z;
  params.inv_two_sigma_sq = 1.0f / (2.0f * fusion.confidence_sigma * fusion.confidence_sigma);
  params.inv_centre_norm_sq = static_cast<float>(1.0 / (camera.cx * camera.cx + camera.cy * camera.cy));
  params.radius_update_ratio = fusion.radius_update_ratio;
  params.mean_focal_px = static_cast<float>(0.5 * (std::abs(camera.fx) + std::abs(camera.fy)));
  params.capacity = map.capacity;
  params.pose_position_variance_m2 = static_cast<float>(uncertainty.position_variance_m2);
  params.pose_rotation_variance_rad2 = static_cast<float>(uncertainty.rotation_variance_rad2);
  params.depth_sigma_a_m = fusion.depth_noise.a_m;
  params.depth_sigma_b_per_m = fusion.depth_noise.b_per_m;
  params.depth_sigma_z0_m = fusion.depth_noise.z0_m;
  return params;
}

}  // namespace vifusion::map
