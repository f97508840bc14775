// Per-iteration parameters of the rotation-only pre-alignment, in a host-written storage buffer (record
// once, change only this between Gauss-Newton iterations). Mirrored by vifusion::tracking::RotationParams
// (pipeline/tracking/include/vifusion/tracking/rotation_params.hpp).
#ifndef VIFUSION_TRACKING_ROTATION_PARAMS_GLSL
#define VIFUSION_TRACKING_ROTATION_PARAMS_GLSL

struct RotationParams {
  vec4 R_prev_cur_rows[3];  // rows of the rotation current camera → previous camera (w unused)
  float fx, fy, cx, cy;     // intrinsics at this level [px]; fy may be negative
  int width, height;        // image size at this level [px]
  float sigma_intensity;    // intensity noise σ_I (0..255 scale) of each image
  float huber_k;            // Huber threshold on r/σ, σ² = 2σ_I² (two noisy images)
  float min_gradient;       // ‖∇I_prev‖ below this carries no information [intensity/px]
  int border_px;            // current pixels this close to the border are not used (blurred, clamped)
  int pad0, pad1;
};

#endif
