#include "vifusion/tracking/icp_cpu.hpp"

#include <Eigen/Geometry>
#include <cmath>

#include "pose_and_camera.hpp"

namespace vifusion::tracking {

NormalEquations6 icpNormalEquationsCpu(ImageView<const preprocess::VertexPixel> current_vertices,
                                       ImageView<const preprocess::NormalPixel> current_normals,
                                       ImageView<const preprocess::VertexPixel> model_vertices,
                                       ImageView<const preprocess::NormalPixel> model_normals,
                                       const IcpParams& params) {
  using Eigen::Vector3f;
  using Eigen::Vector4f;
  const RowTransform T_ref_cur(params);
  NormalEquations6 sum;
  for (int y = 0; y < params.height; ++y) {
    for (int x = 0; x < params.width; ++x) {
      const Vector4f& p = current_vertices(x, y);
      if (!(p.z() > 0.0f)) continue;
      const Vector3f q = T_ref_cur.point(p);
      if (!(q.z() > 0.0f)) continue;
      const int u = static_cast<int>(std::floor(params.fx * q.x() / q.z() + params.cx + 0.5f));
      const int v = static_cast<int>(std::floor(params.fy * q.y() / q.z() + params.cy + 0.5f));
      if (u < 0 || u >= params.width || v < 0 || v >= params.height) continue;
      const Vector4f& model_v = model_vertices(u, v);
      const Vector4f& model_n = model_normals(u, v);
      const Vector4f& cur_n = current_normals(x, y);
      if (!(model_v.z() > 0.0f) || model_n.w() == 0.0f || cur_n.w() == 0.0f) continue;
      sum.addCandidate();
      const Vector3f diff = q - model_v.head<3>();
      if (diff.squaredNorm() > params.max_distance_m * params.max_distance_m) continue;
      const Vector3f rotated_n = T_ref_cur.direction(cur_n.head<3>());
      const Vector3f normal_cross = rotated_n.cross(model_n.head<3>());
      if (normal_cross.squaredNorm() > params.max_normal_sin * params.max_normal_sin) continue;

      const Vector3f n = model_n.head<3>();
      const float r = n.dot(diff);
      const float dz = p.z() - params.sigma_z_z0_m;
      const float sigma = params.sigma_z_a_m + params.sigma_z_b_per_m * dz * dz;
      const float normalised = std::abs(r) / sigma;
      const float huber = normalised <= params.huber_k ? 1.0f : params.huber_k / normalised;
      const Vector3f qxn = q.cross(n);
      Eigen::Matrix<double, 6, 1> J;
      J << n.cast<double>(), qxn.cast<double>();
      const float bias_lever_m2 = std::abs(p.w() * p.w() - model_v.w() * model_v.w());
      sum.addRow(J, r, huber / (sigma * sigma), params.inverse_depth_bias_sigma_per_m * bias_lever_m2);
    }
  }
  return sum;
}

}  // namespace vifusion::tracking
