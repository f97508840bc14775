#include "vifusion/scene/pixel_footprint.hpp"

namespace vifusion::scene {

Eigen::Matrix2d stJacobian(const SurfaceHit& hit, const Eigen::Vector3d& direction_W,
                           const Eigen::Vector3d& ddirection_du_W, const Eigen::Vector3d& ddirection_dv_W) {
  // p = o + t·d on the plane n·p = c gives t = (c − n·o)/(n·d), so ∂p = t·(∂d − (n·∂d)/(n·d)·d).
  // n·d ≠ 0 for any hit: the slab test never picks a face the ray runs parallel to.
  const double n_d = hit.normal_W.dot(direction_W);
  const auto dp = [&](const Eigen::Vector3d& ddirection_W) -> Eigen::Vector3d {
    return hit.t * (ddirection_W - (hit.normal_W.dot(ddirection_W) / n_d) * direction_W);
  };
  const Eigen::Vector3d dp_du_W = dp(ddirection_du_W);
  const Eigen::Vector3d dp_dv_W = dp(ddirection_dv_W);
  Eigen::Matrix2d J_st_px;
  J_st_px << hit.s_axis_W.dot(dp_du_W), hit.s_axis_W.dot(dp_dv_W), hit.t_axis_W.dot(dp_du_W), hit.t_axis_W.dot(dp_dv_W);
  return J_st_px;
}

}  // namespace vifusion::scene
