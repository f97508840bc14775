#pragma once
// Residuals of one frame pair with known poses: frame a's pixels warped into frame b by the ground truth and
// compared with what b measured there. Noise in a and b is independent, so the residuals' variance is twice
// the sensor's, and their spatial correlation is the sensor's (the warp between nearby views is near a shift).
//
// For pixel u of a with inverse depth ι_a(u): p_b = T_b_a · π⁻¹(u, 1/ι_a(u)), u' = π(p_b), c = round(u'),
// δ = u' − c ∈ [−½, ½]² px. On a plane, inverse depth is affine in the pixel, so b's value at u' is
//   ι_b(u') = ι_b(c) + ∇ι_b(c)·δ,   ∇ by central differences over ±kStencilHalfWidth_px,
// exact up to noise, and the depth residual is r_ι = ι_b(u') − 1/z(p_b) [1/m]. The gradient is kept too:
// noise in where a pixel samples the surface (lateral noise) shows as σ_px·‖∇ι‖. The wide stencil keeps the
// gradient's noise small: it adds at most 2·(1/12)·(1/8) of one pixel's variance, 1 % of the residual's.
// A bias b left in inverse depth (1/z_raw = 1/z + b, RigCalibration::inverse_depth_bias_per_m) does not cancel
// between the frames when depth changes: r_ι gains k·b, k = ∂r_ι/∂b = 1 + ∇ι_b·∂u'/∂b − ∂(1/z(p_b))/∂b, where b
// moves p_b by −z_a²·R_b_a·π⁻¹(u, 1) (a's depth) — which makes b observable from pairs that move along the view. The
// intensity residual is likewise I_b(u') − I_a(u) on the 0–255 scale, before any brightness change between the frames
// is removed (noise_estimator.hpp).
//
// Gates (a residual is NaN where one fails): every stencil tap has depth; the stencil lies on one smooth
// surface, |ι(c+2) − 2ι(c) + ι(c−2)| ≤ max_relative_curvature · ι(c) along both axes in b and around u in a
// (a depth edge between taps gives ≥ 20 %; the noise's 2.45 σ_ι is 1.4 % of ι at 4 m for σ_d = 0.05 px at
// f·b = 36 px·m); for intensity, the
// second difference is below max_intensity_curvature (strong texture edges, where the linear correction is
// off, are skipped). Occlusions pass the gates; the estimator's robust trimming removes them.

#include "vifusion/core/image.hpp"
#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/core/se3.hpp"

namespace vifusion::calib {

/// Half-width of the gradient stencil [px].
inline constexpr int kStencilHalfWidth_px = 2;

struct PairResidualOptions {
  /// Largest second difference of inverse depth over the stencil as a share of ι, in (0, 1) (see above).
  double max_relative_curvature = 0.1;
  /// Largest second difference of the grey level over the stencil [0–255 scale], > 0: eight times the
  /// second difference's noise √6·σ for σ ≤ 1.6 (real sensors), four times it for the simulator's σ ≈ 2.7.
  double max_intensity_curvature = 32.0;

  /// Throws vifusion::Error naming the field out of range.
  void validate() const;
};

/// Residuals on frame a's pixel grid; NaN where a gate failed or a pixel left b's image.
struct PairResidualImages {
  Image<float> inverse_depth_residual_per_m;  ///< r_ι [1/m]
  Image<float> depth_b_m;                     ///< z(p_b): the depth the residual's noise belongs to [m]
  Image<float> inverse_depth_gradient_sq;     ///< ‖∇ι_b(c)‖² [(1/m)²/px²], for the lateral noise term
  Image<float> bias_sensitivity;              ///< k = ∂r_ι/∂b [1] (see above)
  Image<float> grey_b_at_a;                   ///< I_b(u') [0–255]
  Image<float> grey_gradient_sq;              ///< ‖∇I_b(c)‖² [grey²/px²]
  Image<float> grey_a;                        ///< I_a(u) [0–255]

  /// Sizes every image to width × height (allocates only when the size changes).
  void resize(int width, int height);
};

/// Fills `out` (resized to a's size when it differs) from inverse depth and grey images of frames a and b
/// (frame_signals.hpp) and the ground-truth motion T_b_a (p_b = T_b_a · p_a).
void computePairResiduals(const PinholeCamera& camera, ImageView<const float> inverse_depth_a,
                          ImageView<const float> grey_a, ImageView<const float> inverse_depth_b,
                          ImageView<const float> grey_b, const SE3d& T_b_a, const PairResidualOptions& options,
                          PairResidualImages& out);

}  // namespace vifusion::calib
