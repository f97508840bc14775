// Per-iteration parameters of the photometric term, in a host-written storage buffer (record once,
// change only this between Gauss-Newton iterations). Mirrored by
// vifusion::tracking::PhotometricParams (pipeline/tracking/include/vifusion/tracking/photometric_params.hpp).
#ifndef VIFUSION_TRACKING_PHOTOMETRIC_PARAMS_GLSL
#define VIFUSION_TRACKING_PHOTOMETRIC_PARAMS_GLSL

struct PhotometricParams {
  vec4 T_ref_cur_rows[3];      // rows of the 3×4 transform current camera → reference camera [m]
  float fx, fy, cx, cy;        // intrinsics at this level [px]; fy may be negative
  int width, height;           // image size at this level [px]
  float sigma_intensity;       // intensity noise σ_I (0..255 scale)
  float huber_k;               // Huber threshold on r/σ (σ² = σ_I² + σ_px²·‖∇I_ref‖²)
  float min_gradient;          // ‖∇I_ref‖ below this carries no information [intensity/px]
  float max_depth_difference_m;  // occlusion gate |q.z − z_ref| [m]
  float sigma_position_px;     // positional σ of the reference image [px]: adds (σ_px·‖∇I_ref‖)² to σ_I²
  int support_radius_px;       // reference depth must be valid on [x0−r+1, x0+r]² around the sample's cell
  int use_reference_fill;      // 1: filled-in reference pixels (vertex w = 0) count as model, 0: the map's only
  int pad0, pad1, pad2;
};

#endif
