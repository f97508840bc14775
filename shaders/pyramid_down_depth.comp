#version 450
// pyramid_down_depth: halves metric depth for the next pyramid level. Output pixel (x, y) is centred
// on input pixel (2x, 2y) and smoothed with the separable 5-tap Gaussian (preprocess/common.glsl),
// using only neighbours inside the image, valid, and within range_gate_m of the centre, normalised
// by the weights used. This keeps depth edges sharp (no averaging across a discontinuity). An
// invalid centre gives an invalid output.
//
// Bindings (set 0, std430 storage buffers, images row-major and tightly packed):
//   0  fine_m    readonly   float[]  metric depth [m], src_width × src_height, 0 = invalid
//   1  coarse_m  writeonly  float[]  metric depth [m], (src_width/2) × (src_height/2) (floor), 0 = invalid
// Push constants: PyramidDownDepthParams (vifusion/preprocess/kernel_params.hpp).
// CPU reference: pyramidDownDepthCpu. One invocation per output (coarse) pixel.
#extension GL_GOOGLE_include_directive : require
#include "preprocess/common.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(local_size_x_id = 0, local_size_y_id = 1) in;

layout(push_constant) uniform Params {
  int src_width;       // fine width [px]
  int src_height;      // fine height [px]
  float range_gate_m;  // largest |neighbour − centre| still averaged [m], inclusive
} params;

layout(set = 0, binding = 0, std430) restrict readonly buffer Fine { float fine_m[]; };
layout(set = 0, binding = 1, std430) restrict writeonly buffer Coarse { float coarse_m[]; };

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  const int dst_width = params.src_width / 2;
  if (pixel.x >= dst_width || pixel.y >= params.src_height / 2) return;

  const int out_index = pixelIndex(pixel, dst_width);
  const ivec2 centre = 2 * pixel;
  const float centre_m = fine_m[pixelIndex(centre, params.src_width)];
  if (!isValidDepth(centre_m)) {
    coarse_m[out_index] = 0.0;
    return;
  }

  float weight_sum = 0.0;
  float weighted_depth_sum = 0.0;
  for (int dy = -2; dy <= 2; ++dy) {
    const int y = centre.y + dy;
    if (y < 0 || y >= params.src_height) continue;
    for (int dx = -2; dx <= 2; ++dx) {
      const int x = centre.x + dx;
      if (x < 0 || x >= params.src_width) continue;
      const float d_m = fine_m[pixelIndex(ivec2(x, y), params.src_width)];
      if (!isValidDepth(d_m) || abs(d_m - centre_m) > params.range_gate_m) continue;
      const float weight = kPyramidWeights[dx + 2] * kPyramidWeights[dy + 2];
      weight_sum += weight;
      weighted_depth_sum += weight * d_m;
    }
  }
  coarse_m[out_index] = weighted_depth_sum / weight_sum;
}
