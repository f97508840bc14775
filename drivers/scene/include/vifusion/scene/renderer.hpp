#pragma once
// Ray-cast rendering of the living room into registered colour and depth images, rows spread over a
// RowPool.
//
// Depth is one ray through the pixel centre, z along the optical axis (not the ray length), as depth
// cameras and the TUM format store it: a depth sensor does not average across edges.
//
// Colour is antialiased the way a camera integrates light over a pixel, because point samples of
// fine texture alias differently from every viewpoint and bias photometric alignment:
//   - on a face, the texture is averaged analytically over the pixel's footprint, found by ray
//     differentials (pixel_footprint.hpp, texture.hpp), widened by a small optics blur: no extra
//     rays, exact for the linear parts of the textures (stripes, joints, grain, lines);
//   - where the centre rays of a pixel's 4-neighbours do not all hit its face (silhouettes, creases,
//     seams between objects), the pixel is resolved as multisample antialiasing does it: N×N
//     stratified sub-rays measure how much of the pixel each face covers, and each face is shaded
//     once, at the centroid of its sub-rays, with its texture averaged as above. A straight edge that
//     crosses a pixel always separates its centre from one of those neighbours' centres, so every
//     pixel an edge crosses is found (features that fit between two centres can be missed).
// Everything is a pure function of the pose and the pixel: the same inputs give the same bytes, for
// any thread count.
//
// Shading is albedo × (ambient + diffuse·(1 + n·l)/2) for a fixed directional light l (a "half-
// Lambert" term, so no face is left at the ambient floor): colour depends only on the surface normal
// and the albedo, never on the viewpoint, so the photometric error of a correct pose is zero before
// noise.

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
  /// Average textures over each pixel's footprint; false point-samples them (aliasing).
  bool filter_textures = true;
  /// σ of the lens blur [px], a Gaussian point-spread function added to the pixel's own box: textures
  /// are averaged over the box of the same variance, 1/12 + σ² [px²]. A pixel box alone still passes
  /// 64 % of the contrast at the Nyquist frequency and aliases what lies just above it; real optics
  /// (and demosaicing) blur about this much. Geometric edges keep the pixel box (see above).
  double optics_blur_sigma_px = 0.3;
  /// N: edge pixels are resolved with N×N sub-rays (N odd reuses the centre ray); 1 turns the edge
  /// resolve off. With filter_textures = false and N = 1, colour is the plain one-ray point sample.
  int edge_samples_per_axis = 3;

  static constexpr int kMaxEdgeSamplesPerAxis = 8;
  static constexpr double kMaxOpticsBlurSigma_px = 2.0;  ///< beyond this the image is not a sharp camera's

  /// Throws std::invalid_argument naming the first option that is out of range.
  void validate() const;
};

class Renderer {
 public:
  /// Keeps references to room and pool, which must outlive the renderer. Validates options.
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

  /// Motion blur: colour is the mean of (antialiased) renders at the sub-frame poses T_W_C_samples
  /// (spread over the exposure, in order); depth comes from the middle sample, index size/2, as a
  /// depth camera's short-exposure image would. Throws std::invalid_argument for an empty span.
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
};

}  // namespace vifusion::scene
