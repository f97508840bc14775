#pragma once
// Ray-cast rendering of the living room into registered colour and depth images, one ray per pixel
// through the pixel centre, rows spread over a RowPool.
//
// Shading is albedo × (ambient + diffuse·(1 + n·l)/2) for a fixed directional light l (a "half-
// Lambert" term, so no face is left at the ambient floor): colour depends only on the surface normal
// and the albedo, never on the viewpoint, so the photometric error of a correct pose is zero before
// noise. Depth is z along the optical axis (not the ray length), as depth cameras and the TUM format
// store it.

#include <Eigen/Core>
#include <cstdint>
#include <span>

#include "vifusion/core/image.hpp"
#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/scene/living_room.hpp"
#include "vifusion/scene/row_pool.hpp"

namespace vifusion::scene {

struct RenderOptions {
  double depth_scale = 5000.0;  ///< depth-image units per metre (TUM / ICL-NUIM PNG convention)
  double max_range_m = 10.0;    ///< depth beyond this reads 0 (no measurement); colour is still rendered
  Eigen::Vector3d light_direction_W{0.35, 0.85, 0.4};  ///< towards the light; normalised by the renderer
  double ambient = 0.3;                                ///< shading floor, fraction of albedo
  double diffuse = 0.7;                                ///< weight of the half-Lambert term, fraction of albedo
};

class Renderer {
 public:
  /// Keeps references to room and pool, which must outlive the renderer.
  Renderer(const LivingRoom& room, RowPool& pool, const RenderOptions& options = {});

  /// Renders camera pose T_W_C (vision axes: x right, y down, z forward) with `camera` (fy may be
  /// negative) into rgb and depth [depth_scale units per metre; 0 = no hit, beyond max_range_m, or
  /// not representable in 16 bits]. Either view may be empty to skip it; a non-empty view must have
  /// the camera's size (std::invalid_argument otherwise). Allocates nothing.
  void render(const SE3d& T_W_C, const PinholeCamera& camera, ImageView<Rgb8> rgb,
              ImageView<std::uint16_t> depth) const;
  /// The same with unquantised depth in metres (0 = no measurement): the exact input the sensor-noise
  /// model and the geometry tests need.
  void render(const SE3d& T_W_C, const PinholeCamera& camera, ImageView<Rgb8> rgb, ImageView<float> depth_m) const;

  /// Motion blur: colour is the mean of renders at the sub-frame poses T_W_C_samples (spread over the
  /// exposure, in order); depth comes from the middle sample, index size/2, as a depth camera's
  /// short-exposure image would. Throws std::invalid_argument for an empty span.
  void renderBlurred(std::span<const SE3d> T_W_C_samples, const PinholeCamera& camera, ImageView<Rgb8> rgb,
                     ImageView<std::uint16_t> depth) const;
  void renderBlurred(std::span<const SE3d> T_W_C_samples, const PinholeCamera& camera, ImageView<Rgb8> rgb,
                     ImageView<float> depth_m) const;

  const RenderOptions& options() const { return options_; }

 private:
  template <class Depth>
  void renderImpl(std::span<const SE3d> T_W_C_samples, const PinholeCamera& camera, ImageView<Rgb8> rgb,
                  ImageView<Depth> depth) const;

  const LivingRoom& room_;
  RowPool& pool_;
  RenderOptions options_;
  Eigen::Vector3d light_W_;  ///< unit vector towards the light
};

}  // namespace vifusion::scene
