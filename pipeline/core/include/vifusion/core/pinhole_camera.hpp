#pragma once
// Pinhole camera without distortion, in the vision convention (x right, y down, z forward).
// fy may be negative: ICL-NUIM renders with fy = −480, which flips the image rows; the model
// stays exact because projection and back-projection use the signed value consistently.

#include <Eigen/Core>
#include <optional>
#include <string>

namespace vifusion {

struct PinholeCamera {
  int width = 0;    ///< image width [px]
  int height = 0;   ///< image height [px]
  double fx = 0.0;  ///< focal length along u [px], > 0
  double fy = 0.0;  ///< focal length along v [px], non-zero, may be negative (ICL-NUIM)
  double cx = 0.0;  ///< principal point u [px], pixel centres at integer coordinates
  double cy = 0.0;  ///< principal point v [px]

  /// Validated construction: throws std::invalid_argument naming the bad parameter.
  static PinholeCamera create(int width, int height, double fx, double fy, double cx, double cy);

  /// Intrinsics of pyramid level `level`, matching the preprocessing pyramids: level-l pixel j is
  /// the Gaussian-weighted sample centred on level-0 pixel 2^l·j, so f_l = f_0 / 2^l and
  /// c_l = c_0 / 2^l. Sizes are floor(size_0 / 2^l); throws
  /// std::invalid_argument for level < 0 or a level that leaves no pixel.
  PinholeCamera atLevel(int level) const;

  /// Projects p_C (z > 0 [m], asserted in debug builds) to pixel coordinates. J_uv_p (optional)
  /// receives ∂uv/∂p_C [px/m].
  Eigen::Vector2d project(const Eigen::Vector3d& p_C, Eigen::Matrix<double, 2, 3>* J_uv_p = nullptr) const;

  /// Back-projects pixel uv at depth z_m (distance along the optical axis) to p_C.
  Eigen::Vector3d backProject(const Eigen::Vector2d& uv, double z_m) const;

  /// True when border_px ≤ u ≤ width − 1 − border_px and likewise for v (pixel centres are integers,
  /// so this is the range bilinear interpolation covers). NaN coordinates are outside.
  bool isInside(const Eigen::Vector2d& uv, double border_px = 0.0) const;
};

}  // namespace vifusion
