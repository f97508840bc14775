#pragma once
// Parameters of the surfel fusion kernels: the user-facing options (ElasticFusion's gates and
// confidence model, algorithms.md §1.3/§1.5) and the per-frame block the shaders read, a std430
// mirror of FusionParams in shaders/include/map/fusion_params.glsl shared verbatim by the CPU
// references, so a parameter cannot mean one thing on the GPU and another on the CPU.

#include <cstddef>
#include <cstdint>

#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/map/surfel.hpp"

namespace vifusion::map {

/// The sensor's axial depth noise σ_z(z) = a + b·(z − z0)² [m]. Not a fusion setting: the owner copies
/// the tracker's model (tracking::IcpOptions), so one noise model weights tracking and fusion alike.
struct AxialDepthNoise {
  float a_m = 0.0f;
  float b_per_m = 0.0f;
  float z0_m = 0.0f;
};

/// The uncertainty of the pose a frame is fused at. Zero for a frame the dense terms registered to the
/// map (its points agree with the map to the registration's residuals); the estimator's marginal
/// variances for a frame the IMU carried, which weight its measurements down (poseWeight in
/// shaders/include/map/fusion_params.glsl).
struct FusionPoseUncertainty {
  double position_variance_m2 = 0.0;   ///< largest marginal variance of the camera position [m²], ≥ 0
  double rotation_variance_rad2 = 0.0; ///< largest marginal variance of the camera rotation [rad²], ≥ 0
};

/// Data association and fusion gates; defaults are ElasticFusion's.
struct FusionOptions {
  float max_depth_diff_m = 0.05f;     ///< candidate gate on |z_surfel − z_pixel| along the pixel ray [m]
  float max_normal_angle_rad = 0.5f;  ///< candidate gate on the angle between surfel and pixel normals
  float grazing_normal_z = 0.75f;     ///< surfels with |n_C.z| below this skip the normal gate
  float confidence_sigma = 0.6f;      ///< σ of the radial confidence exp(−γ²/(2σ²)) [1]
  float radius_update_ratio = 1.5f;   ///< geometry is fused only when r_new < ratio · r_old
  /// Weights measurements fused at an uncertain pose; set by the owner (see AxialDepthNoise). Only used
  /// with a non-zero FusionPoseUncertainty.
  AxialDepthNoise depth_noise;

  /// Throws vifusion::Error naming the field that is out of range.
  void validate() const;
};

/// The pixel-match markers besides surfel index + 1 (mirror fusion_params.glsl).
inline constexpr std::uint32_t kPixelNoMeasurement = 0;
inline constexpr std::uint32_t kPixelNewSurfel = 0xFFFFFFFFu;
/// surfel_claim value of a surfel no pixel claimed this frame.
inline constexpr std::uint32_t kUnclaimed = 0xFFFFFFFFu;

/// std430 mirror of FusionParams in the shaders (48 four-byte words, no implicit padding).
struct FusionParams {
  float T_C_W_rows[3][4] = {};           ///< rows of the 3×4 transform W → C [m]
  float T_W_C_rows[3][4] = {};           ///< rows of the 3×4 transform C → W [m]
  float fx = 0, fy = 0, cx = 0, cy = 0;  ///< level-0 intrinsics [px]; fy may be negative
  std::int32_t width = 0, height = 0;    ///< level-0 image size [px]
  std::uint32_t frame = 0;               ///< current frame number
  std::uint32_t time_window_frames = 0;  ///< δ_t [frames]
  float max_depth_m = 0;
  float max_depth_diff_m = 0;
  float min_normal_cos = 0;
  float grazing_normal_z = 0;
  float inv_two_sigma_sq = 0;
  float inv_centre_norm_sq = 0;  ///< [1/px²]
  float radius_update_ratio = 0;
  float mean_focal_px = 0;
  std::uint32_t capacity = 0;
  float pose_position_variance_m2 = 0;
  float pose_rotation_variance_rad2 = 0;
  float depth_sigma_a_m = 0, depth_sigma_b_per_m = 0, depth_sigma_z0_m = 0;
  std::uint32_t pad[2] = {};

  /// Everything for fusing frame `frame` taken at pose T_W_C (with `uncertainty`) with the level-0 `camera`.
  static FusionParams make(const SE3d& T_W_C, std::uint32_t frame, const PinholeCamera& camera, const MapOptions& map,
                           const FusionOptions& fusion, const FusionPoseUncertainty& uncertainty = {});
};
static_assert(sizeof(FusionParams) == 192);
static_assert(offsetof(FusionParams, T_W_C_rows) == 48);
static_assert(offsetof(FusionParams, fx) == 96);
static_assert(offsetof(FusionParams, width) == 112);
static_assert(offsetof(FusionParams, frame) == 120);
static_assert(offsetof(FusionParams, max_depth_m) == 128);
static_assert(offsetof(FusionParams, mean_focal_px) == 156);
static_assert(offsetof(FusionParams, capacity) == 160);
static_assert(offsetof(FusionParams, pose_position_variance_m2) == 164);
static_assert(offsetof(FusionParams, depth_sigma_z0_m) == 180);

}  // namespace vifusion::map
