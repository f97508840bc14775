// Per-iteration parameters of the ICP term, in a host-written storage buffer so that the command
// buffer is recorded once and only this buffer changes between Gauss-Newton iterations.
// Mirrored by vifusion::tracking::IcpParams (pipeline/tracking/include/vifusion/tracking/icp_params.hpp).
#ifndef VIFUSION_TRACKING_ICP_PARAMS_GLSL
#define VIFUSION_TRACKING_ICP_PARAMS_GLSL

struct IcpParams {
  vec4 T_ref_cur_rows[3];  // rows of the 3×4 transform current camera → reference (model) camera [m]
  float fx, fy, cx, cy;    // reference camera intrinsics at this level [px]; fy may be negative
  int width, height;       // image size at this level [px] (current and model maps alike)
  float max_distance_m;    // association gate on ‖q − v_model‖ [m]
  float max_normal_sin;    // association gate on ‖n_cur × n_model‖ (sine of the angle)
  float sigma_z_a_m;       // depth noise σ_z(z) = a + b·(z − z0)² [m]
  float sigma_z_b_per_m;   // [1/m]
  float sigma_z_z0_m;      // [m]
  float huber_k;           // Huber threshold on the normalised residual r/σ
  float inverse_depth_bias_sigma_per_m;  // σ_b of the calibration's uncorrected 1/z bias [1/m] (0: none)
  float pad0, pad1, pad2;
};

#endif
