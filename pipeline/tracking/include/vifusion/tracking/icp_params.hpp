#pragma once
// Parameters of the point-to-plane ICP term, shared verbatim by the shader (a storage buffer with
// the layout of shaders/include/tracking/icp_params.glsl) and the CPU reference.

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/core/se3.hpp"

namespace vifusion::tracking {

/// Association gates and noise model; defaults follow ElasticFusion's gates (10 cm, 20°) and a
/// Kinect-style axial noise σ_z = 1.2 mm + 1.9 mm/m²·(z − 0.4 m)² (Nguyen et al. 2012).
struct IcpOptions {
  float max_distance_m = 0.10f;
  float max_normal_angle_rad = 20.0f * 3.14159265f / 180.0f;
  float sigma_z_a_m = 0.0012f;
  float sigma_z_b_per_m = 0.0019f;
  float sigma_z_z0_m = 0.4f;
  float huber_k = 3.0f;  ///< residuals beyond 3σ are down-weighted as outliers
  /// σ_b of the inverse-depth bias the rig's calibration left uncorrected [1/m], ≥ 0 (calibration.yaml's
  /// depth_noise; 0: none known). That error b is one for every frame: it moves a point observed from depth z
  /// by b·z² along its ray, so two surfaces fused from the same depth move alike and only the difference of
  /// their observation depths z_obs (the vertices' w; frames carry 1) shows in a residual. Each row's systematic
  /// error is taken as e = σ_b·|z_obs,cur² − z_obs,ref²|: exact to first order in the angle between the two
  /// observation rays, which the maps do not keep. Only model registration reads the bound
  /// (NormalEquations6::weighted_squared_bound); tracking's steps and tests do not.
  float inverse_depth_bias_sigma_per_m = 0.0f;

  /// The sensor's axial depth noise σ_z(z) = a + b·(z − z0)² at camera depth z [m] (the kernel's model).
  double axialSigmaAt(double z_m) const {
    const double dz_m = z_m - sigma_z_z0_m;
    return sigma_z_a_m + sigma_z_b_per_m * dz_m * dz_m;
  }

  /// Throws vifusion::Error naming the field that is not positive or out of range.
  void validate() const;
};

/// std430 mirror of IcpParams in the shader (28 floats: the struct's size is a multiple of its vec4 alignment).
struct IcpParams {
  float T_ref_cur_rows[3][4] = {};  ///< rows of the 3×4 transform current → reference camera [m]
  float fx = 0, fy = 0, cx = 0, cy = 0;
  std::int32_t width = 0, height = 0;
  float max_distance_m = 0;
  float max_normal_sin = 0;
  float sigma_z_a_m = 0;
  float sigma_z_b_per_m = 0;
  float sigma_z_z0_m = 0;
  float huber_k = 0;
  float inverse_depth_bias_sigma_per_m = 0;
  float pad[3] = {};

  static IcpParams make(const SE3d& T_ref_cur, const PinholeCamera& camera, const IcpOptions& options);
};
static_assert(sizeof(IcpParams) == 28 * 4);
static_assert(offsetof(IcpParams, fx) == 48);
static_assert(offsetof(IcpParams, width) == 64);
static_assert(offsetof(IcpParams, max_distance_m) == 72);
static_assert(offsetof(IcpParams, huber_k) == 92);
static_assert(offsetof(IcpParams, inverse_depth_bias_sigma_per_m) == 96);

}  // namespace vifusion::tracking
