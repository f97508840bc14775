#pragma once
// Fills the fields every dense-term parameter block starts with: the 3×4 transform current →
// reference camera (rows, float) and the level's intrinsics and size.

#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/core/se3.hpp"

namespace vifusion::tracking {

template <typename Params>
void setPoseAndCamera(Params& params, const SE3d& T_ref_cur, const PinholeCamera& camera) {
  const Eigen::Matrix4d T = T_ref_cur.matrix();
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 4; ++col) params.T_ref_cur_rows[row][col] = static_cast<float>(T(row, col));
  }
  params.fx = static_cast<float>(camera.fx);
  params.fy = static_cast<float>(camera.fy);
  params.cx = static_cast<float>(camera.cx);
  params.cy = static_cast<float>(camera.cy);
  params.width = camera.width;
  params.height = camera.height;
}

}  // namespace vifusion::tracking
