#include "vifusion/tracking/photometric_cpu.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "pose_and_camera.hpp"

namespace vifusion::tracking {

NormalEquations6 photometricNormalEquationsCpu(ImageView<const preprocess::VertexPixel> current_vertices,
                                               ImageView<const float> current_intensity,
                                               ImageView<const float> reference_intensity,
                                               ImageView<const preprocess::GradientPixel> reference_gradients,
                                               ImageView<const preprocess::VertexPixel> reference_vertices,
                                               const PhotometricParams& params) {
  using Eigen::Vector2f;
  using Eigen::Vector3f;
  using Eigen::Vector4f;
  const RowTransform T_ref_cur(params);
  NormalEquations6 sum;
  for (int py = 0; py < params.height; ++py) {
    for (int px = 0; px < params.width; ++px) {
      const Vector4f& p = current_vertices(px, py);
      if (!(p.z() > 0.0f)) continue;
      sum.addCandidate();
      const Vector3f q = T_ref_cur.point(p);
      if (!(q.z() > 0.0f)) continue;
      const float inv_z = 1.0f / q.z();
      const float x = params.fx * q.x() * inv_z + params.cx;
      const float y = params.fy * q.y() * inv_z + params.cy;
      if (!(x >= 0.0f && y >= 0.0f && x < static_cast<float>(params.width - 1) &&
            y < static_cast<float>(params.height - 1))) {
        continue;
      }
      const int x0 = static_cast<int>(x);
      const int y0 = static_cast<int>(y);
      const float ax = x - static_cast<float>(x0);
      const float ay = y - static_cast<float>(y0);
      const Vector4f& nearest = reference_vertices(x0 + (ax >= 0.5f ? 1 : 0), y0 + (ay >= 0.5f ? 1 : 0));
      if (!params.onModel(nearest) || std::abs(q.z() - nearest.z()) > params.max_depth_difference_m) continue;

      const float w00 = (1.0f - ax) * (1.0f - ay), w10 = ax * (1.0f - ay), w01 = (1.0f - ax) * ay, w11 = ax * ay;
      const float intensity = w00 * reference_intensity(x0, y0) + w10 * reference_intensity(x0 + 1, y0) +
                              w01 * reference_intensity(x0, y0 + 1) + w11 * reference_intensity(x0 + 1, y0 + 1);
      const Vector2f gradient = w00 * reference_gradients(x0, y0) + w10 * reference_gradients(x0 + 1, y0) +
                                w01 * reference_gradients(x0, y0 + 1) + w11 * reference_gradients(x0 + 1, y0 + 1);
      if (gradient.squaredNorm() < params.min_gradient * params.min_gradient) continue;
      bool supported = true;
      for (int dy = 1 - params.support_radius_px; dy <= params.support_radius_px && supported; ++dy) {
        const int row = std::clamp(y0 + dy, 0, params.height - 1);
        for (int dx = 1 - params.support_radius_px; dx <= params.support_radius_px; ++dx) {
          if (!params.onModel(reference_vertices(std::clamp(x0 + dx, 0, params.width - 1), row))) {
            supported = false;
            break;
          }
        }
      }
      if (!supported) continue;

      const float r = intensity - current_intensity(px, py);
      const Vector3f g(gradient.x() * params.fx * inv_z, gradient.y() * params.fy * inv_z,
                       -(gradient.x() * params.fx * q.x() + gradient.y() * params.fy * q.y()) * inv_z * inv_z);
      const Vector3f qxg = q.cross(g);
      const float variance = params.sigma_intensity * params.sigma_intensity +
                             params.sigma_position_px * params.sigma_position_px * gradient.squaredNorm();
      const float normalised = std::abs(r) / std::sqrt(variance);
      const float huber = normalised <= params.huber_k ? 1.0f : params.huber_k / normalised;
      Eigen::Matrix<double, 6, 1> J;
      J << g.cast<double>(), qxg.cast<double>();
      sum.addRow(J, r, huber / variance);
    }
  }
  return sum;
}

}  // namespace vifusion::tracking
