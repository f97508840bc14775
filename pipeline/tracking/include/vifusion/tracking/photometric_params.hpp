#pragma once
// Parameters of the photometric term, shared verbatim by the shader (a storage buffer with the
// layout of shaders/include/tracking/photometric_params.glsl) and the CPU reference.

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>

#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/core/se3.hpp"

namespace vifusion::tracking {

/// Defaults: σ_I = 4 (the paper's Table I, synthetic data; 1 for the real sensor), ElasticFusion's
/// 7 cm occlusion gate; gradients below 3 intensity/px carry no information worth its noise.
struct PhotometricOptions {
  float sigma_intensity = 4.0f;
  float huber_k = 3.0f;
  float min_gradient = 3.0f;
  float max_depth_difference_m = 0.07f;
  /// Positional uncertainty of the reference image [px]: the model is predicted by splatting
  /// surfels whose colours were sampled up to half a pixel away from where they now project, so an
  /// intensity there is uncertain by σ_px·‖∇I‖ on top of the sensor noise: σ² = σ_I² + (σ_px·‖∇I‖)².
  /// Without it the strongest edges, the least reliable pixels, dominate the alignment. A uniform
  /// half-pixel offset alone is 0.29 px; 1 px also covers the coarse levels' residual error seen at
  /// level 0 (measured, noise-free 640×480: 0.29 px → 8 mm after one frame, 1 px → 0.7 mm).
  float sigma_position_px = 1.0f;

  /// Throws vifusion::Error naming the field that is not finite and positive.
  void validate() const;
};

/// std430 mirror of PhotometricParams in the shader (28 words: the struct's size is a multiple of its vec4
/// alignment).
struct PhotometricParams {
  float T_ref_cur_rows[3][4] = {};
  float fx = 0, fy = 0, cx = 0, cy = 0;
  std::int32_t width = 0, height = 0;
  float sigma_intensity = 0;
  float huber_k = 0;
  float min_gradient = 0;
  float max_depth_difference_m = 0;
  float sigma_position_px = 0;
  /// The reference pixels a sample at cell (x0, y0) depends on are [x0−r+1, x0+r]² (r = this): the
  /// bilinear 2×2, widened by the gradient's 3×3 Sobel (r = 2) and at coarse levels by the Gaussian
  /// pyramid that built the reference intensity from level 0 (r = 3). All of them must lie on valid
  /// model pixels: a hole of the prediction has intensity 0, so its border is an edge that the scene
  /// does not have (measured on sim:living_room_1 frame 186, 49 % of the view unpredicted: it pulled
  /// level 2 by 136 mm along the wall and started the run-away).
  std::int32_t support_radius_px = 0;
  /// 1: reference pixels filled in from the previous frame (vertex w = 0, slam/reference_fill.hpp) count as
  /// model pixels; 0: only the map's prediction (w ≠ 0) does. The fill is the fallback of a frame the map
  /// alone cannot track.
  std::int32_t use_reference_fill = 0;
  std::int32_t pad[3] = {};

  /// `level` is the pyramid level of `camera` (0 = full resolution); it sets support_radius_px.
  static PhotometricParams make(const SE3d& T_ref_cur, const PinholeCamera& camera, const PhotometricOptions& options,
                                int level = 0, bool use_reference_fill = false);
  /// Whether a reference vertex is a model pixel under these parameters (valid depth, and predicted by the
  /// map unless the fill is in use): the photometric_reduce.comp test.
  bool onModel(const Eigen::Vector4f& reference_vertex) const {
    return reference_vertex.z() > 0.0f && (use_reference_fill != 0 || reference_vertex.w() != 0.0f);
  }
};
static_assert(sizeof(PhotometricParams) == 28 * 4);
static_assert(offsetof(PhotometricParams, width) == 64);
static_assert(offsetof(PhotometricParams, max_depth_difference_m) == 84);
static_assert(offsetof(PhotometricParams, sigma_position_px) == 88);
static_assert(offsetof(PhotometricParams, support_radius_px) == 92);
static_assert(offsetof(PhotometricParams, use_reference_fill) == 96);

}  // namespace vifusion::tracking
