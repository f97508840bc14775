#include "vifusion/map/fusion_cpu.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

#include "vifusion/preprocess/packing.hpp"

namespace vifusion::map {
namespace {

// Mirrors of shaders/include/map/fusion_params.glsl, operation for operation (left-to-right sums,
// no fused multiply-add), so that integer decisions match the GPU bit for bit.

Eigen::Vector3f transformPoint(const float (&rows)[3][4], const Eigen::Vector3f& p) {
  Eigen::Vector3f out;
  for (int r = 0; r < 3; ++r) out[r] = rows[r][0] * p.x() + rows[r][1] * p.y() + rows[r][2] * p.z() + rows[r][3];
  return out;
}

Eigen::Vector3f rotateVector(const float (&rows)[3][4], const Eigen::Vector3f& n) {
  Eigen::Vector3f out;
  for (int r = 0; r < 3; ++r) out[r] = rows[r][0] * n.x() + rows[r][1] * n.y() + rows[r][2] * n.z();
  return out;
}

struct Pixel {
  int x = 0;
  int y = 0;
};

Pixel projectToPixel(const FusionParams& params, const Eigen::Vector3f& p_C) {
  const float u = params.fx * p_C.x() / p_C.z() + params.cx;
  const float v = params.fy * p_C.y() / p_C.z() + params.cy;
  return {static_cast<int>(std::floor(u + 0.5f)), static_cast<int>(std::floor(v + 0.5f))};
}

Pixel pixelOf(const FusionParams& params, std::uint32_t index) {
  const auto width = static_cast<std::uint32_t>(params.width);
  return {static_cast<int>(index % width), static_cast<int>(index / width)};
}

float poseWeight(const FusionParams& params, float z_m) {
  const float pose_variance_at_unit_depth = params.pose_position_variance_m2 + params.pose_rotation_variance_rad2;
  if (!(pose_variance_at_unit_depth > 0.0f)) return 1.0f;
  const float dz = z_m - params.depth_sigma_z0_m;
  const float sigma_z = params.depth_sigma_a_m + params.depth_sigma_b_per_m * dz * dz;
  const float sensor_variance = sigma_z * sigma_z;
  return sensor_variance /
         (sensor_variance + params.pose_position_variance_m2 + z_m * z_m * params.pose_rotation_variance_rad2);
}

float measurementConfidence(const FusionParams& params, Pixel pixel, float z_m) {
  const float du = static_cast<float>(pixel.x) - params.cx;
  const float dv = static_cast<float>(pixel.y) - params.cy;
  const float gamma_sq = (du * du + dv * dv) * params.inv_centre_norm_sq;
  return std::exp(-gamma_sq * params.inv_two_sigma_sq) * poseWeight(params, z_m);
}

float measurementRadius(const FusionParams& params, float z_m, float n_z) {
  const float radius_m = 1.41421356f * z_m / params.mean_focal_px;
  const float cos_view = std::abs(n_z);
  return cos_view * 2.0f > 1.0f ? radius_m / cos_view : 2.0f * radius_m;
}

Eigen::Vector3f rgbOfPixel(std::span<const std::uint32_t> rgb_words, std::uint32_t i) {
  Eigen::Vector3f rgb;
  for (std::uint32_t c = 0; c < 3; ++c) {
    const std::uint32_t byte = 3 * i + c;
    rgb[static_cast<int>(c)] = static_cast<float>(preprocess::byteOfWord(rgb_words[byte >> 2], byte));
  }
  return rgb;
}

bool isActive(const Surfel& s, const FusionParams& params) {
  return s.position_confidence.w() > 0.0f &&
         !(static_cast<float>(params.frame) - s.colour_times.z() > static_cast<float>(params.time_window_frames));
}

}  // namespace

void indexMapCpu(std::span<const Surfel> surfels, std::uint32_t surfel_count, const FusionParams& params,
                 std::span<std::uint32_t> index_depth, std::span<std::uint32_t> index_id) {
  std::fill(index_depth.begin(), index_depth.end(), 0xFFFFFFFFu);
  std::fill(index_id.begin(), index_id.end(), 0u);
  for (std::uint32_t id = 0; id < surfel_count; ++id) {
    const Surfel& s = surfels[id];
    if (!isActive(s, params)) continue;
    const Eigen::Vector3f p_C = transformPoint(params.T_C_W_rows, s.position_confidence.head<3>());
    if (!(p_C.z() > 0.0f) || p_C.z() > params.max_depth_m) continue;
    const Pixel pixel = projectToPixel(params, p_C);
    if (pixel.x < 0 || pixel.x >= params.width || pixel.y < 0 || pixel.y >= params.height) continue;
    const std::size_t i = static_cast<std::size_t>(pixel.y) * params.width + pixel.x;
    const std::uint32_t z_bits = std::bit_cast<std::uint32_t>(p_C.z());
    // Both GPU passes at once: a nearer surfel replaces the winner, an equally near one with a
    // higher index too (atomicMax of id + 1 in pass 1).
    if (z_bits < index_depth[i] || (z_bits == index_depth[i] && id + 1 > index_id[i])) {
      index_depth[i] = z_bits;
      index_id[i] = id + 1;
    }
  }
}

void associateCpu(const MeasurementMaps& frame, std::span<const Surfel> surfels,
                  std::span<const std::uint32_t> index_id, const FusionParams& params,
                  std::span<std::uint32_t> pixel_match, std::span<std::uint32_t> surfel_claim) {
  std::fill(surfel_claim.begin(), surfel_claim.end(), kUnclaimed);
  const float depth_diff_sq = params.max_depth_diff_m * params.max_depth_diff_m;
  for (int v = 0; v < params.height; ++v) {
    for (int u = 0; u < params.width; ++u) {
      const auto i = static_cast<std::uint32_t>(v * params.width + u);
      const Eigen::Vector4f& p = frame.vertices(u, v);
      const Eigen::Vector4f& n = frame.normals(u, v);
      if (!(p.z() > 0.0f) || p.z() > params.max_depth_m || n.w() == 0.0f) {
        pixel_match[i] = kPixelNoMeasurement;
        continue;
      }
      const float p_sq = p.x() * p.x() + p.y() * p.y() + p.z() * p.z();
      const float depth_gate = depth_diff_sq * p.z() * p.z();
      std::uint32_t best = 0;
      float best_distance = 0.0f;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int x = u + dx;
          const int y = v + dy;
          if (x < 0 || x >= params.width || y < 0 || y >= params.height) continue;
          const std::uint32_t candidate = index_id[static_cast<std::size_t>(y) * params.width + x];
          if (candidate == 0) continue;
          const Surfel& s = surfels[candidate - 1];
          const Eigen::Vector3f x_C = transformPoint(params.T_C_W_rows, s.position_confidence.head<3>());
          const Eigen::Vector3f m_C = rotateVector(params.T_C_W_rows, s.normal_radius.head<3>());
          const float dz = x_C.z() - p.z();
          const float depth_term = dz * dz * p_sq;
          if (!(depth_term < depth_gate)) continue;
          const float normal_cos = m_C.x() * n.x() + m_C.y() * n.y() + m_C.z() * n.z();
          if (!(normal_cos > params.min_normal_cos) && !(std::abs(m_C.z()) < params.grazing_normal_z)) continue;
          const float cx = x_C.y() * p.z() - x_C.z() * p.y();
          const float cy = x_C.z() * p.x() - x_C.x() * p.z();
          const float cz = x_C.x() * p.y() - x_C.y() * p.x();
          const float distance = cx * cx + cy * cy + cz * cz;
          if (best == 0 || distance < best_distance || (distance == best_distance && candidate < best)) {
            best = candidate;
            best_distance = distance;
          }
        }
      }
      if (best == 0) {
        pixel_match[i] = kPixelNewSurfel;
        continue;
      }
      pixel_match[i] = best;
      surfel_claim[best - 1] = std::min(surfel_claim[best - 1], i);
    }
  }
}

void fuseCpu(const MeasurementMaps& frame, const FusionParams& params, std::span<const std::uint32_t> surfel_claim,
             std::uint32_t surfel_count, std::span<Surfel> surfels) {
  for (std::uint32_t id = 0; id < surfel_count; ++id) {
    const std::uint32_t pixel_index = surfel_claim[id];
    if (pixel_index == kUnclaimed) continue;
    const Pixel pixel = pixelOf(params, pixel_index);
    const Eigen::Vector4f& p = frame.vertices(pixel.x, pixel.y);
    const Eigen::Vector4f& n = frame.normals(pixel.x, pixel.y);
    const float alpha = measurementConfidence(params, pixel, p.z());
    const float radius_m = measurementRadius(params, p.z(), n.z());

    Surfel& s = surfels[id];
    const float c = s.position_confidence.w();
    if (radius_m < params.radius_update_ratio * s.normal_radius.w()) {
      const float w = c + alpha;
      const Eigen::Vector3f p_W = transformPoint(params.T_W_C_rows, p.head<3>());
      const Eigen::Vector3f n_W = rotateVector(params.T_W_C_rows, n.head<3>());
      const Eigen::Vector3f rgb = rgbOfPixel(frame.rgb_words, pixel_index);
      s.position_confidence.head<3>() = (c * s.position_confidence.head<3>() + alpha * p_W) / w;
      const Eigen::Vector3f normal = (c * s.normal_radius.head<3>() + alpha * n_W) / w;
      const float normal_sq = normal.dot(normal);
      if (normal_sq > 1e-12f) s.normal_radius.head<3>() = normal / std::sqrt(normal_sq);
      s.normal_radius.w() = (c * s.normal_radius.w() + alpha * radius_m) / w;
      s.setPackedColour(packRgb8((c * unpackRgb8(s.packedColour()) + alpha * rgb) / w));
    }
    s.position_confidence.w() = c + alpha;
    s.colour_times.z() = static_cast<float>(params.frame);
  }
}

void insertCpu(const MeasurementMaps& frame, const FusionParams& params, std::span<const std::uint32_t> pixel_match,
               MapState& state, std::span<Surfel> surfels) {
  const std::uint32_t capacity = params.capacity;
  std::uint32_t next = state.surfel_count;
  for (std::uint32_t i = 0; i < pixel_match.size(); ++i) {
    if (pixel_match[i] != kPixelNewSurfel) continue;
    const std::uint32_t index = next++;
    if (index >= capacity) continue;
    const Pixel pixel = pixelOf(params, i);
    const Eigen::Vector4f& p = frame.vertices(pixel.x, pixel.y);
    const Eigen::Vector4f& n = frame.normals(pixel.x, pixel.y);
    Surfel& s = surfels[index];
    s.position_confidence.head<3>() = transformPoint(params.T_W_C_rows, p.head<3>());
    s.position_confidence.w() = measurementConfidence(params, pixel, p.z());
    s.normal_radius.head<3>() = rotateVector(params.T_W_C_rows, n.head<3>());
    s.normal_radius.w() = measurementRadius(params, p.z(), n.z());
    s.colour_times = Eigen::Vector4f(0.0f, static_cast<float>(params.frame), static_cast<float>(params.frame), 0.0f);
    s.setPackedColour(packRgb8(rgbOfPixel(frame.rgb_words, i)));
  }
  const std::uint32_t kept = std::min(next, capacity);
  state.overflow_count += next - kept;
  state.surfel_count = kept;
  state.frame = params.frame;
}

}  // namespace vifusion::map
