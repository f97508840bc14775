#include "native_loops.hpp"

#include <algorithm>
#include <cmath>

namespace vifusion::bench {
namespace {

/// Adds w·JᵀJ (upper triangle), w·J·r, w·r² and one inlier.
inline void accumulate(const float J[6], float r, float w, NativeSums& sums) {
  int k = 0;
  for (int i = 0; i < 6; ++i) {
    const double wJi = double(w) * J[i];
    for (int j = i; j < 6; ++j) sums[k++] += wJi * J[j];
    sums[21 + i] += wJi * r;
  }
  sums[27] += double(w) * r * r;
  sums[28] += 1.0;
}

/// The shader's support gate: every reference pixel of [x0−r+1, x0+r]² (clamped to the image) has
/// a predicted vertex.
inline bool supportedByModel(const preprocess::VertexPixel* reference_vertices, const tracking::PhotometricParams& params,
                             int x0, int y0) {
  const int r = params.support_radius_px;
  for (int dy = 1 - r; dy <= r; ++dy) {
    const int row = std::clamp(y0 + dy, 0, params.height - 1) * params.width;
    for (int dx = 1 - r; dx <= r; ++dx) {
      if (!(reference_vertices[row + std::clamp(x0 + dx, 0, params.width - 1)].z() > 0.0f)) return false;
    }
  }
  return true;
}

}  // namespace

void icpNative(const preprocess::VertexPixel* current_vertices, const preprocess::NormalPixel* current_normals,
               const preprocess::VertexPixel* model_vertices, const preprocess::NormalPixel* model_normals,
               const tracking::IcpParams& params, int begin, int end, NativeSums& sums) {
  const auto& T = params.T_ref_cur_rows;
  const float max_distance_sq = params.max_distance_m * params.max_distance_m;
  const float max_sin_sq = params.max_normal_sin * params.max_normal_sin;
  for (int i = begin; i < end; ++i) {
    const float* p = current_vertices[i].data();
    if (!(p[2] > 0.0f)) continue;
    sums[29] += 1.0;
    const float qx = T[0][0] * p[0] + T[0][1] * p[1] + T[0][2] * p[2] + T[0][3];
    const float qy = T[1][0] * p[0] + T[1][1] * p[1] + T[1][2] * p[2] + T[1][3];
    const float qz = T[2][0] * p[0] + T[2][1] * p[1] + T[2][2] * p[2] + T[2][3];
    if (!(qz > 0.0f)) continue;
    const int u = static_cast<int>(std::floor(params.fx * qx / qz + params.cx + 0.5f));
    const int v = static_cast<int>(std::floor(params.fy * qy / qz + params.cy + 0.5f));
    if (u < 0 || u >= params.width || v < 0 || v >= params.height) continue;
    const int j = v * params.width + u;
    const float* mv = model_vertices[j].data();
    const float* mn = model_normals[j].data();
    const float* cn = current_normals[i].data();
    if (!(mv[2] > 0.0f) || mn[3] == 0.0f || cn[3] == 0.0f) continue;
    const float dx = qx - mv[0], dy = qy - mv[1], dz = qz - mv[2];
    if (dx * dx + dy * dy + dz * dz > max_distance_sq) continue;
    const float rx = T[0][0] * cn[0] + T[0][1] * cn[1] + T[0][2] * cn[2];
    const float ry = T[1][0] * cn[0] + T[1][1] * cn[1] + T[1][2] * cn[2];
    const float rz = T[2][0] * cn[0] + T[2][1] * cn[1] + T[2][2] * cn[2];
    const float cx = ry * mn[2] - rz * mn[1], cy = rz * mn[0] - rx * mn[2], cz = rx * mn[1] - ry * mn[0];
    if (cx * cx + cy * cy + cz * cz > max_sin_sq) continue;
    const float r = mn[0] * dx + mn[1] * dy + mn[2] * dz;
    const float depth = p[2] - params.sigma_z_z0_m;
    const float sigma = params.sigma_z_a_m + params.sigma_z_b_per_m * depth * depth;
    const float normalised = std::abs(r) / sigma;
    const float huber = normalised <= params.huber_k ? 1.0f : params.huber_k / normalised;
    const float J[6] = {mn[0], mn[1], mn[2], qy * mn[2] - qz * mn[1], qz * mn[0] - qx * mn[2], qx * mn[1] - qy * mn[0]};
    accumulate(J, r, huber / (sigma * sigma), sums);
  }
}

void photometricNative(const preprocess::VertexPixel* current_vertices, const float* current_intensity,
                       const float* reference_intensity, const preprocess::GradientPixel* reference_gradients,
                       const preprocess::VertexPixel* reference_vertices, const tracking::PhotometricParams& params,
                       int begin, int end, NativeSums& sums) {
  const auto& T = params.T_ref_cur_rows;
  const int w = params.width;
  const float min_gradient_sq = params.min_gradient * params.min_gradient;
  const float sigma_i_sq = params.sigma_intensity * params.sigma_intensity;
  const float sigma_px_sq = params.sigma_position_px * params.sigma_position_px;
  for (int i = begin; i < end; ++i) {
    const float* p = current_vertices[i].data();
    if (!(p[2] > 0.0f)) continue;
    sums[29] += 1.0;
    const float qx = T[0][0] * p[0] + T[0][1] * p[1] + T[0][2] * p[2] + T[0][3];
    const float qy = T[1][0] * p[0] + T[1][1] * p[1] + T[1][2] * p[2] + T[1][3];
    const float qz = T[2][0] * p[0] + T[2][1] * p[1] + T[2][2] * p[2] + T[2][3];
    if (!(qz > 0.0f)) continue;
    const float inv_z = 1.0f / qz;
    const float x = params.fx * qx * inv_z + params.cx;
    const float y = params.fy * qy * inv_z + params.cy;
    if (!(x >= 0.0f && y >= 0.0f && x < float(params.width - 1) && y < float(params.height - 1))) continue;
    const int x0 = static_cast<int>(x);
    const int y0 = static_cast<int>(y);
    const float ax = x - float(x0);
    const float ay = y - float(y0);
    const int j = y0 * w + x0;
    const float z_ref = reference_vertices[j + (ay >= 0.5f ? w : 0) + (ax >= 0.5f ? 1 : 0)].z();
    if (!(z_ref > 0.0f) || std::abs(qz - z_ref) > params.max_depth_difference_m) continue;
    const float w00 = (1.0f - ax) * (1.0f - ay), w10 = ax * (1.0f - ay), w01 = (1.0f - ax) * ay, w11 = ax * ay;
    const float intensity = w00 * reference_intensity[j] + w10 * reference_intensity[j + 1] +
                            w01 * reference_intensity[j + w] + w11 * reference_intensity[j + w + 1];
    const float gx = w00 * reference_gradients[j].x() + w10 * reference_gradients[j + 1].x() +
                     w01 * reference_gradients[j + w].x() + w11 * reference_gradients[j + w + 1].x();
    const float gy = w00 * reference_gradients[j].y() + w10 * reference_gradients[j + 1].y() +
                     w01 * reference_gradients[j + w].y() + w11 * reference_gradients[j + w + 1].y();
    const float gradient_sq = gx * gx + gy * gy;
    if (gradient_sq < min_gradient_sq) continue;
    if (!supportedByModel(reference_vertices, params, x0, y0)) continue;
    const float r = intensity - current_intensity[i];
    const float g0 = gx * params.fx * inv_z, g1 = gy * params.fy * inv_z;
    const float g2 = -(gx * params.fx * qx + gy * params.fy * qy) * inv_z * inv_z;
    const float variance = sigma_i_sq + sigma_px_sq * gradient_sq;
    const float normalised = std::abs(r) / std::sqrt(variance);
    const float huber = normalised <= params.huber_k ? 1.0f : params.huber_k / normalised;
    const float J[6] = {g0, g1, g2, qy * g2 - qz * g1, qz * g0 - qx * g2, qx * g1 - qy * g0};
    accumulate(J, r, huber / variance, sums);
  }
}

}  // namespace vifusion::bench
