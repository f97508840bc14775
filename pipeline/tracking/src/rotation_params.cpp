#include "vifusion/tracking/rotation_params.hpp"

namespace vifusion::tracking {
namespace {

/// The Sobel kernel's reach (1 px) plus one for the pyramid's Gaussian at the border.
constexpr std::int32_t kRotationBorderPx = 2;

}  // namespace

RotationParams RotationParams::make(const Eigen::Quaterniond& q_prev_cur, const PinholeCamera& camera,
                                    const PhotometricOptions& options) {
  RotationParams params;
  const Eigen::Matrix3d R = q_prev_cur.toRotationMatrix();
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) params.R_prev_cur_rows[row][col] = static_cast<float>(R(row, col));
  }
  params.fx = static_cast<float>(camera.fx);
  params.fy = static_cast<float>(camera.fy);
  params.cx = static_cast<float>(camera.cx);
  params.cy = static_cast<float>(camera.cy);
  params.width = camera.width;
  params.height = camera.height;
  params.sigma_intensity = options.sigma_intensity;
  params.huber_k = options.huber_k;
  params.min_gradient = options.min_gradient;
  params.border_px = kRotationBorderPx;
  return params;
}

}  // namespace vifusion::tracking
