// Per-frame parameters of the surfel fusion kernels (map_index, map_associate, map_fuse, map_insert)
// in a host-written storage buffer, so the command buffer is recorded once and only this buffer
// changes between frames. Mirrored by vifusion::map::FusionParams
// (pipeline/map/include/vifusion/map/fusion_params.hpp), whose CPU references (fusion_cpu.cpp)
// repeat every function below operation for operation.
//
// Arithmetic that decides an integer result (pixel of a surfel, winner of a depth test or of a
// candidate comparison) is written out term by term into `precise` variables: no fused
// multiply-add, no reassociation, so the GPU and the CPU reference agree bit for bit.
#ifndef VIFUSION_MAP_FUSION_PARAMS_GLSL
#define VIFUSION_MAP_FUSION_PARAMS_GLSL

struct FusionParams {
  vec4 T_C_W_rows[3];         // rows of the 3×4 transform world W → camera C [m]
  vec4 T_W_C_rows[3];         // rows of the 3×4 transform camera C → world W [m]
  float fx, fy, cx, cy;       // level-0 intrinsics [px]; fy may be negative
  int width, height;          // level-0 image size [px] (index map and measurement maps)
  uint frame;                 // current frame number (surfel times are frame numbers)
  uint time_window_frames;    // δ_t: a surfel is active when frame − updated ≤ δ_t
  float max_depth_m;          // surfels farther than this are not in the index map [m]
  float max_depth_diff_m;     // association gate on |z_surfel − z_pixel| along the ray [m]
  float min_normal_cos;       // association gate: cos of the largest normal angle
  float grazing_normal_z;     // surfels with |n_C.z| below this pass the normal gate (grazing view)
  float inv_two_sigma_sq;     // 1/(2σ²) of the radial confidence α = exp(−γ²/(2σ²))
  float inv_centre_norm_sq;   // 1/‖(cx, cy)‖² [1/px²]: γ = ‖(u, v) − (cx, cy)‖ / ‖(cx, cy)‖
  float radius_update_ratio;  // a measurement updates geometry only if r_new < ratio · r_old
  float mean_focal_px;        // f̄ = (|fx| + |fy|)/2 for the surfel radius [px]
  uint capacity;              // surfels the map array holds
  // The fusion pose's own uncertainty (0 for a frame registered to the map by the dense terms) and the
  // sensor's axial noise σ_z(z) = a + b·(z − z0)², which together weight a measurement: poseWeight().
  float pose_position_variance_m2;   // largest marginal variance of the camera position [m²]
  float pose_rotation_variance_rad2; // largest marginal variance of the camera rotation [rad²]
  float depth_sigma_a_m;             // a [m]
  float depth_sigma_b_per_m;         // b [1/m]
  float depth_sigma_z0_m;            // z0 [m]
  uint pad0, pad1;
};

// The no-surfel and new-surfel markers of the per-pixel match buffer (values 1..capacity are
// surfel index + 1).
const uint kPixelNoMeasurement = 0u;
const uint kPixelNewSurfel = 0xFFFFFFFFu;
// surfel_claim value of a surfel that no pixel claimed this frame.
const uint kUnclaimed = 0xFFFFFFFFu;

vec3 transformPoint(const vec4 rows[3], vec3 p) {
  precise float x = rows[0].x * p.x + rows[0].y * p.y + rows[0].z * p.z + rows[0].w;
  precise float y = rows[1].x * p.x + rows[1].y * p.y + rows[1].z * p.z + rows[1].w;
  precise float z = rows[2].x * p.x + rows[2].y * p.y + rows[2].z * p.z + rows[2].w;
  return vec3(x, y, z);
}

vec3 rotateVector(const vec4 rows[3], vec3 n) {
  precise float x = rows[0].x * n.x + rows[0].y * n.y + rows[0].z * n.z;
  precise float y = rows[1].x * n.x + rows[1].y * n.y + rows[1].z * n.z;
  precise float z = rows[2].x * n.x + rows[2].y * n.y + rows[2].z * n.z;
  return vec3(x, y, z);
}

// Nearest pixel of a camera-frame point with z > 0. floor(x + 0.5), not round(): GLSL leaves the
// direction of halves to the implementation.
ivec2 projectToPixel(FusionParams params, vec3 p_C) {
  precise float u = params.fx * p_C.x / p_C.z + params.cx;
  precise float v = params.fy * p_C.y / p_C.z + params.cy;
  return ivec2(int(floor(u + 0.5)), int(floor(v + 0.5)));
}

// The share of a measurement at depth z that its frame's pose leaves trustworthy: the inverse-variance
// weight σ_z² / (σ_z² + σ_p²) of a point whose sensor noise σ_z(z) is joined by the pose's σ_p² =
// σ_r² + z²·σ_θ² (translation, and rotation swinging the point by z·θ). 1 exactly for a registered frame.
float poseWeight(FusionParams params, float z_m) {
  const float pose_variance_at_unit_depth = params.pose_position_variance_m2 + params.pose_rotation_variance_rad2;
  if (!(pose_variance_at_unit_depth > 0.0)) return 1.0;
  const float dz = z_m - params.depth_sigma_z0_m;
  const float sigma_z = params.depth_sigma_a_m + params.depth_sigma_b_per_m * dz * dz;
  const float sensor_variance = sigma_z * sigma_z;
  return sensor_variance /
         (sensor_variance + params.pose_position_variance_m2 + z_m * z_m * params.pose_rotation_variance_rad2);
}

// ElasticFusion's radial confidence of a measurement at pixel (u, v) — 1 at the principal point,
// ≈ 0.25 in the corners of a 640 × 480 image — times the pose weight at its depth z.
float measurementConfidence(FusionParams params, ivec2 pixel, float z_m) {
  const float du = float(pixel.x) - params.cx;
  const float dv = float(pixel.y) - params.cy;
  const float gamma_sq = (du * du + dv * dv) * params.inv_centre_norm_sq;
  return exp(-gamma_sq * params.inv_two_sigma_sq) * poseWeight(params, z_m);
}

// ElasticFusion's surfel radius: the pixel footprint √2·z/f̄, enlarged by 1/|n_z| for surfaces seen
// at an angle, at most twice. n_z is the camera-frame normal's z.
float measurementRadius(FusionParams params, float z_m, float n_z) {
  const float radius_m = 1.41421356 * z_m / params.mean_focal_px;
  const float cos_view = abs(n_z);
  return cos_view * 2.0 > 1.0 ? radius_m / cos_view : 2.0 * radius_m;
}

// The pixel runs map_associate and map_insert share: each image row cut into segments of
// run_pixels (the last one shorter), numbered in pixel order, so run r covers the pixels
// [first, end) of row `row` and the runs of a frame are pixelRunCount of them.
uint pixelRunsPerRow(FusionParams params, uint run_pixels) { return (uint(params.width) + run_pixels - 1u) / run_pixels; }

uint pixelRunCount(FusionParams params, uint run_pixels) { return uint(params.height) * pixelRunsPerRow(params, run_pixels); }

// (first, end, row) of run r; first = end when r is past the last run.
uvec3 pixelRun(FusionParams params, uint run_pixels, uint r) {
  if (r >= pixelRunCount(params, run_pixels)) return uvec3(0u);
  const uint per_row = pixelRunsPerRow(params, run_pixels);
  const uint row = r / per_row;
  const uint u = (r - row * per_row) * run_pixels;
  const uint first = row * uint(params.width) + u;
  return uvec3(first, first + min(run_pixels, uint(params.width) - u), row);
}

// Colour of pixel i from the packed RGB888 upload (3 bytes a pixel, see preprocess/packing.glsl).
// Reads rgb_words[] of the including shader.
#define FUSION_RGB_OF_PIXEL(rgb_words, i)                                                   \
  vec3(float(byteOfWord(rgb_words[(3u * (i)) >> 2], 3u * (i))),                             \
       float(byteOfWord(rgb_words[(3u * (i) + 1u) >> 2], 3u * (i) + 1u)),                   \
       float(byteOfWord(rgb_words[(3u * (i) + 2u) >> 2], 3u * (i) + 2u)))

#endif
