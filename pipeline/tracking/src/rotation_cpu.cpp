#include "vifusion/tracking/rotation_cpu.hpp"

#include <cmath>

namespace vifusion::tracking {

NormalEquations6 rotationNormalEquationsCpu(ImageView<const float> current_intensity,
                                            ImageView<const float> previous_intensity,
                                            ImageView<const preprocess::GradientPixel> previous_gradients,
                                            const RotationParams& params) {
  using Eigen::Vector2f;
  using Eigen::Vector3f;
  Eigen::Matrix3f R;
  for (int row = 0; row < 3; ++row) {
    R.row(row) << params.R_prev_cur_rows[row][0], params.R_prev_cur_rows[row][1], params.R_prev_cur_rows[row][2];
  }
  NormalEquations6 sum;
  const int border = params.border_px;
  for (int v = border; v < params.height - border; ++v) {
    for (int u = border; u < params.width - border; ++u) {
      sum.addCandidate();
      const Vector3f ray((static_cast<float>(u) - params.cx) / params.fx,
                         (static_cast<float>(v) - params.cy) / params.fy, 1.0f);
      const Vector3f q(R.row(0).dot(ray), R.row(1).dot(ray), R.row(2).dot(ray));
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
      const float w00 = (1.0f - ax) * (1.0f - ay), w10 = ax * (1.0f - ay), w01 = (1.0f - ax) * ay, w11 = ax * ay;
      const float intensity = w00 * previous_intensity(x0, y0) + w10 * previous_intensity(x0 + 1, y0) +
                              w01 * previous_intensity(x0, y0 + 1) + w11 * previous_intensity(x0 + 1, y0 + 1);
      const Vector2f gradient = w00 * previous_gradients(x0, y0) + w10 * previous_gradients(x0 + 1, y0) +
                                w01 * previous_gradients(x0, y0 + 1) + w11 * previous_gradients(x0 + 1, y0 + 1);
      if (gradient.squaredNorm() < params.min_gradient * params.min_gradient) continue;

      const float r = intensity - current_intensity(u, v);
      const Vector3f g(gradient.x() * params.fx * inv_z, gradient.y() * params.fy * inv_z,
                       -(gradient.x() * params.fx * q.x() + gradient.y() * params.fy * q.y()) * inv_z * inv_z);
      const Vector3f qxg = q.cross(g);
      const float variance = 2.0f * params.sigma_intensity * params.sigma_intensity;
      const float normalised = std::abs(r) / std::sqrt(variance);
      const float huber = normalised <= params.huber_k ? 1.0f : params.huber_k / normalised;
      Eigen::Matrix<double, 6, 1> J;
      J << 0.0, 0.0, 0.0, qxg.cast<double>();
      sum.addRow(J, r, huber / variance);
    }
  }
  return sum;
}

}  // namespace vifusion::tracking
