#pragma once
// Fills the fields every dense-term parameter block starts with (the 3×4 transform current →
// reference camera as float rows, the level's intrinsics and size), and applies those rows on the
// CPU exactly as the shaders do.

#include <Eigen/Core>

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

/// The CPU references' view of T_ref_cur_rows: q = T·p with the same float dot products the
/// shaders use (dot(row, vec4(p, 1))).
class RowTransform {
 public:
  template <typename Params>
  explicit RowTransform(const Params& params) {
    for (int r = 0; r < 3; ++r) {
      rows_[r] = Eigen::Vector4f(params.T_ref_cur_rows[r][0], params.T_ref_cur_rows[r][1], params.T_ref_cur_rows[r][2],
                                 params.T_ref_cur_rows[r][3]);
    }
  }
  /// T·p for a point p (w = 1).
  Eigen::Vector3f point(const Eigen::Vector4f& p) const {
    const Eigen::Vector4f p1(p.x(), p.y(), p.z(), 1.0f);
    return {rows_[0].dot(p1), rows_[1].dot(p1), rows_[2].dot(p1)};
  }
  /// R·n for a direction n.
  Eigen::Vector3f direction(const Eigen::Vector3f& n) const {
    return {rows_[0].head<3>().dot(n), rows_[1].head<3>().dot(n), rows_[2].head<3>().dot(n)};
  }

 private:
  Eigen::Vector4f rows_[3];
};

}  // namespace vifusion::tracking
