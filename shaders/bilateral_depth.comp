#version 450
// bilateral_depth: edge-preserving smoothing of metric depth (ElasticFusion's 13 × 13 window and
// σ_space 4.5 px; σ_range = range_sigmas · σ_z(z_centre), the sensor's axial noise at the centre
// pixel's depth, so quantisation steps that grow with z² are smoothed at every range). Neighbours that are invalid or outside the image are
// skipped and the result is normalised by the weights used, so holes and borders do not pull
// depth towards 0; an invalid centre stays invalid.
//
// Bindings (set 0, std430 storage buffers, images row-major and tightly packed, width × height):
//   0  depth_in   readonly   float[]  metric depth [m], 0 = invalid
//   1  depth_out  writeonly  float[]  filtered metric depth [m], 0 = invalid
// Push constants: BilateralDepthParams (vifusion/preprocess/kernel_params.hpp).
// CPU reference: bilateralDepthCpu. One invocation per output pixel. Radius 0 (filter off) is not
// dispatched: PreprocessStage records a buffer copy instead.
#extension GL_GOOGLE_include_directive : require
#include "preprocess/common.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(local_size_x_id = 0, local_size_y_id = 1) in;

layout(push_constant) uniform Params {
  int width;             // [px]
  int height;            // [px]
  int radius_px;         // window half-size [px]; the window is (2r+1)²
  float sigma_space_px;  // spatial standard deviation [px]
  float range_sigmas;    // σ_range in units of σ_z(z) [1]
  float noise_a_m;       // σ_z(z) = a + b·(z − z0)² [m]
  float noise_b_per_m;   // [1/m]
  float noise_z0_m;      // [m]
} params;

layout(set = 0, binding = 0, std430) restrict readonly buffer DepthIn { float depth_in[]; };
layout(set = 0, binding = 1, std430) restrict writeonly buffer DepthOut { float depth_out[]; };

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= params.width || pixel.y >= params.height) return;

  const int centre = pixelIndex(pixel, params.width);
  const float centre_m = depth_in[centre];
  if (!isValidDepth(centre_m)) {
    depth_out[centre] = 0.0;
    return;
  }

  const float space_coeff = 0.5 / (params.sigma_space_px * params.sigma_space_px);  // 1/(2σ_s²) [1/px²]
  const float dz_m = centre_m - params.noise_z0_m;
  const float sigma_range_m = params.range_sigmas * (params.noise_a_m + params.noise_b_per_m * dz_m * dz_m);
  const float range_coeff = 0.5 / (sigma_range_m * sigma_range_m);  // 1/(2σ_r²) [1/m²]
  const int r = params.radius_px;
  const float inverse_centre = 1.0 / centre_m;
  float weight_sum = 0.0;
  float weighted_inverse_sum = 0.0;
  for (int dy = -r; dy <= r; ++dy) {
    const int y = pixel.y + dy;
    if (y < 0 || y >= params.height) continue;
    for (int dx = -r; dx <= r; ++dx) {
      const int x = pixel.x + dx;
      if (x < 0 || x >= params.width) continue;
      const float d_m = depth_in[pixelIndex(ivec2(x, y), params.width)];
      if (!isValidDepth(d_m)) continue;
      // Depth difference seen from the centre's depth: z_c²·(1/d − 1/z_c), symmetric for symmetric
      // neighbours on a plane (inverse depth is linear in (u, v) there).
      const float inverse_d = 1.0 / d_m;
      const float diff_m = centre_m * centre_m * (inverse_d - inverse_centre);
      // One exp of the summed exponents (the centre contributes weight exp(0) = 1, so the sum is ≥ 1).
      const float weight = exp(-(float(dx * dx + dy * dy) * space_coeff) - (diff_m * diff_m) * range_coeff);
      weight_sum += weight;
      weighted_inverse_sum += weight * inverse_d;
    }
  }
  depth_out[centre] = weight_sum / weighted_inverse_sum;
}
