#pragma once
// The colour of one pixel, for the renderer (renderer.hpp): a face's shaded albedo with its texture
// averaged over the pixel's footprint, and the multisample resolve of pixels that straddle edges.

#include <Eigen/Core>
#include <span>

#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/scene/living_room.hpp"
#include "vifusion/scene/renderer.hpp"

namespace vifusion::scene {

/// The pose pieces the ray loops need, per sub-frame pose.
struct RayFrame {
  Eigen::Matrix3d R_W_C = Eigen::Matrix3d::Identity();
  Eigen::Vector3d origin_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d ddirection_du_W = Eigen::Vector3d::Zero();  ///< ∂direction/∂u = R_W_C.col(0)/fx [1/px]
  Eigen::Vector3d ddirection_dv_W = Eigen::Vector3d::Zero();  ///< ∂direction/∂v = R_W_C.col(1)/fy [1/px]

  RayFrame() = default;
  RayFrame(const SE3d& T_W_C, const PinholeCamera& camera);

  /// Direction through pixel (u, v) plus the sub-pixel offset (du, dv) [px], with unit camera z so
  /// that the ray parameter of a hit is its depth. The offset is added after the principal point so
  /// that mirrored offsets give exactly mirrored rays.
  Eigen::Vector3d direction(const PinholeCamera& camera, int u, int v, double du = 0.0, double dv = 0.0) const {
    const double x_n = ((static_cast<double>(u) - camera.cx) + du) / camera.fx;
    const double y_n = ((static_cast<double>(v) - camera.cy) + dv) / camera.fy;
    return R_W_C.col(2) + x_n * R_W_C.col(0) + y_n * R_W_C.col(1);
  }
};

class PixelShader {
 public:
  /// Keeps references to all three, which must outlive the shader (one render call).
  PixelShader(const LivingRoom& room, const PinholeCamera& camera, const RenderOptions& options);

  /// Shaded albedo of `hit`, seen along direction_W from `frame`, with its texture averaged over the
  /// pixel around the ray and the optics blur (point-sampled without options.filter_textures); black
  /// for no hit.
  Albedo shade(const RayFrame& frame, const Eigen::Vector3d& direction_W, const SurfaceHit& hit) const;

  /// Colour of edge pixel (u, v), as multisample antialiasing resolves it: N×N stratified sub-rays
  /// (N = options.edge_samples_per_axis) measure how much of the pixel each face covers, and each face
  /// is shaded once, at the centroid of its sub-rays. Sub-rays are cast against `candidates`, the
  /// boxes the centre rays of the pixel and its 8 neighbours hit (centre is the pixel's own): that is
  /// whatever the pixel sees, short of features that fit between those rays, which edge finding
  /// misses anyway; a sub-ray that hits none of them is cast against the whole room.
  Albedo resolveEdge(const RayFrame& frame, int u, int v, const SurfaceHit& centre,
                     std::span<const Box* const> candidates) const;

 private:
  const LivingRoom& room_;
  const PinholeCamera& camera_;
  const RenderOptions& options_;
  Eigen::Vector3d light_W_;  ///< unit vector towards the light
  /// Texture footprint per pixel footprint: √(1 + 12σ²), the box with the variance of pixel and blur.
  double footprint_scale_;
  float ambient_;
  float diffuse_;
};

}  // namespace vifusion::scene
