#include "vifusion/map/prediction_cpu.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

namespace vifusion::map {
namespace {

// CameraSurfel, observationDepth, footprintOf and splatPixel of prediction.glsl, operation for operation.
struct CameraSurfel {
  Eigen::Vector3f p_C;
  Eigen::Vector3f n_C;
  float radius2_m2 = 0;
};

struct Footprint {
  int x0 = 0, x1 = -1, y0 = 0, y1 = -1;
  int centre_x = -1, centre_y = -1;  ///< the pixel the centre projects into
};

std::uint32_t splatKey(const Footprint& f, int x, int y, float depth_m) {
  const std::uint32_t disk_only = x == f.centre_x && y == f.centre_y ? 0u : 0x80000000u;
  return disk_only | (std::bit_cast<std::uint32_t>(depth_m) >> 1);
}

CameraSurfel toCamera(const Surfel& surfel, const MapView& view) {
  CameraSurfel s;
  s.p_C = transformPointCpu(view, surfel.position_confidence.head<3>());
  s.n_C = rotateVectorCpu(view, surfel.normal_radius.head<3>());
  const float min_radius_m = s.p_C.z() * std::max(std::abs(view.inv_fx), std::abs(view.inv_fy));
  const float radius_m = std::max(surfel.normal_radius.w(), min_radius_m);
  s.radius2_m2 = radius_m * radius_m;
  return s;
}

float observationDepth(const Surfel& surfel, const MapView& view) {
  constexpr float kInverseSqrt2 = 0.70710678f;  // the shader's literal
  const float mean_focal_px = (std::abs(view.fx) + std::abs(view.fy)) * 0.5f;
  return surfel.normal_radius.w() * mean_focal_px * kInverseSqrt2;
}

Footprint footprintOf(const CameraSurfel& s, const PredictionParams& params) {
  Footprint f;
  const MapView& view = params.view;
  const float cap = static_cast<float>(params.max_half_footprint_px);
  const Eigen::Vector2f uv = projectPointCpu(view, s.p_C);
  if (!(uv.x() > -cap - 1.0f && uv.x() < static_cast<float>(view.width) + cap && uv.y() > -cap - 1.0f &&
        uv.y() < static_cast<float>(view.height) + cap)) {
    return f;
  }
  const float inv_z = 1.0f / s.p_C.z();
  const float radius_m = std::sqrt(s.radius2_m2);
  const float half_x = radius_m * std::abs(view.fx) * inv_z;
  const float half_y = radius_m * std::abs(view.fy) * inv_z;
  const float centre_x = std::floor(uv.x() + 0.5f);
  const float centre_y = std::floor(uv.y() + 0.5f);
  f.centre_x = static_cast<int>(centre_x);
  f.centre_y = static_cast<int>(centre_y);
  f.x0 = static_cast<int>(std::max(std::max(std::ceil(uv.x() - half_x), centre_x - cap), 0.0f));
  f.x1 = static_cast<int>(
      std::min(std::min(std::floor(uv.x() + half_x), centre_x + cap), static_cast<float>(view.width - 1)));
  f.y0 = static_cast<int>(std::max(std::max(std::ceil(uv.y() - half_y), centre_y - cap), 0.0f));
  f.y1 = static_cast<int>(
      std::min(std::min(std::floor(uv.y() + half_y), centre_y + cap), static_cast<float>(view.height - 1)));
  return f;
}

bool splatPixel(const CameraSurfel& s, int x, int y, const MapView& view, Eigen::Vector3f& q_C) {
  const float dx = (static_cast<float>(x) - view.cx) * view.inv_fx;
  const float dy = (static_cast<float>(y) - view.cy) * view.inv_fy;
  const float n_dot_d = (s.n_C.x() * dx + s.n_C.y() * dy) + s.n_C.z();
  const float n_dot_p = (s.n_C.x() * s.p_C.x() + s.n_C.y() * s.p_C.y()) + s.n_C.z() * s.p_C.z();
  const float t = n_dot_p * (1.0f / n_dot_d);
  q_C = Eigen::Vector3f(t * dx, t * dy, t);
  const float ex = q_C.x() - s.p_C.x();
  const float ey = q_C.y() - s.p_C.y();
  const float ez = q_C.z() - s.p_C.z();
  const float e2 = (ex * ex + ey * ey) + ez * ez;
  return t > 0.0f && e2 <= s.radius2_m2;
}

}  // namespace

MapView MapView::make(const SE3d& T_C_W, const PinholeCamera& camera, std::uint32_t frame) {
  MapView view;
  const Eigen::Matrix4d T = T_C_W.matrix();
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 4; ++col) view.T_C_W_rows[row][col] = static_cast<float>(T(row, col));
  }
  view.fx = static_cast<float>(camera.fx);
  view.fy = static_cast<float>(camera.fy);
  view.cx = static_cast<float>(camera.cx);
  view.cy = static_cast<float>(camera.cy);
  view.inv_fx = 1.0f / view.fx;
  view.inv_fy = 1.0f / view.fy;
  view.width = camera.width;
  view.height = camera.height;
  view.frame = frame;
  return view;
}

Eigen::Vector3f transformPointCpu(const MapView& view, const Eigen::Vector3f& p_W) {
  Eigen::Vector3f p_C;
  for (int r = 0; r < 3; ++r) {
    const float* row = view.T_C_W_rows[r];
    p_C[r] = ((row[0] * p_W.x() + row[1] * p_W.y()) + row[2] * p_W.z()) + row[3];
  }
  return p_C;
}

Eigen::Vector3f rotateVectorCpu(const MapView& view, const Eigen::Vector3f& n_W) {
  Eigen::Vector3f n_C;
  for (int r = 0; r < 3; ++r) {
    const float* row = view.T_C_W_rows[r];
    n_C[r] = (row[0] * n_W.x() + row[1] * n_W.y()) + row[2] * n_W.z();
  }
  return n_C;
}

Eigen::Vector2f projectPointCpu(const MapView& view, const Eigen::Vector3f& p_C) {
  const float inv_z = 1.0f / p_C.z();
  return {view.fx * (p_C.x() * inv_z) + view.cx, view.fy * (p_C.y() * inv_z) + view.cy};
}

std::uint32_t framesSinceCpu(const MapView& view, float frame_f) {
  const auto frame = static_cast<std::uint32_t>(frame_f);
  return view.frame >= frame ? view.frame - frame : 0u;
}

bool isRenderedCpu(const Surfel& surfel, const PredictionParams& params) {
  const bool active = framesSinceCpu(params.view, surfel.colour_times.z()) <= params.time_window_frames;
  const bool stable = surfel.position_confidence.w() >= params.confidence_threshold;
  if (!(static_cast<std::uint32_t>(surfel.colour_times.y()) < params.created_before)) return false;
  if (params.surfels == static_cast<std::uint32_t>(PredictedSurfels::kInactive)) return !active && stable;
  if (params.surfels == static_cast<std::uint32_t>(PredictedSurfels::kStable)) return stable;
  return active && (stable || params.view.frame < params.young_map_frames);
}

void splatModelCpu(std::span<const Surfel> surfels, const PredictionParams& params, ImageView<std::uint32_t> depth_bits,
                   ImageView<std::uint32_t> ids) {
  for (int y = 0; y < depth_bits.height; ++y) {
    std::fill_n(depth_bits.row(y), depth_bits.width, 0xffffffffu);
    std::fill_n(ids.row(y), ids.width, kNoSurfel);
  }
  // One pass in index order with the (key, index) lexicographic minimum is what the GPU's
  // two atomic passes compute.
  for (std::size_t i = 0; i < surfels.size(); ++i) {
    if (!isRenderedCpu(surfels[i], params)) continue;
    const CameraSurfel s = toCamera(surfels[i], params.view);
    if (!(s.p_C.z() > params.min_depth_m && s.p_C.z() <= params.max_depth_m)) continue;
    const Footprint f = footprintOf(s, params);
    for (int y = f.y0; y <= f.y1; ++y) {
      for (int x = f.x0; x <= f.x1; ++x) {
        Eigen::Vector3f q_C;
        if (!splatPixel(s, x, y, params.view, q_C)) continue;
        const std::uint32_t bits = splatKey(f, x, y, q_C.z());
        if (bits < depth_bits(x, y)) {
          depth_bits(x, y) = bits;
          ids(x, y) = static_cast<std::uint32_t>(i);
        }
      }
    }
  }
}

void resolveModelCpu(std::span<const Surfel> surfels, const PredictionParams& params,
                     ImageView<const std::uint32_t> ids, ImageView<Eigen::Vector4f> vertices,
                     ImageView<Eigen::Vector4f> normals, ImageView<float> intensity) {
  for (int y = 0; y < ids.height; ++y) {
    for (int x = 0; x < ids.width; ++x) {
      const std::uint32_t id = ids(x, y);
      if (id == kNoSurfel) {
        vertices(x, y) = Eigen::Vector4f::Zero();
        normals(x, y) = Eigen::Vector4f::Zero();
        intensity(x, y) = 0.0f;
        continue;
      }
      const Surfel& surfel = surfels[id];
      const CameraSurfel s = toCamera(surfel, params.view);
      Eigen::Vector3f q_C;
      splatPixel(s, x, y, params.view, q_C);
      const float n_dot_q = (s.n_C.x() * q_C.x() + s.n_C.y() * q_C.y()) + s.n_C.z() * q_C.z();
      const Eigen::Vector3f n_C = n_dot_q > 0.0f ? Eigen::Vector3f(-s.n_C) : s.n_C;
      const Eigen::Vector3f rgb = unpackRgb8(surfel.packedColour());
      vertices(x, y) = Eigen::Vector4f(q_C.x(), q_C.y(), q_C.z(), observationDepth(surfel, params.view));
      normals(x, y) = Eigen::Vector4f(n_C.x(), n_C.y(), n_C.z(), 1.0f);
      intensity(x, y) = (0.299f * rgb.x() + 0.587f * rgb.y()) + 0.114f * rgb.z();
    }
  }
}

void subsampleModelCpu(ImageView<const Eigen::Vector4f> vertices0, ImageView<const Eigen::Vector4f> normals0,
                       ImageView<const float> intensity0, int level, ImageView<Eigen::Vector4f> vertices,
                       ImageView<Eigen::Vector4f> normals, ImageView<float> intensity) {
  const int step = 1 << level;
  for (int y = 0; y < vertices.height; ++y) {
    for (int x = 0; x < vertices.width; ++x) {
      vertices(x, y) = vertices0(x * step, y * step);
      normals(x, y) = normals0(x * step, y * step);
      intensity(x, y) = intensity0(x * step, y * step);
    }
  }
}

}  // namespace vifusion::map
