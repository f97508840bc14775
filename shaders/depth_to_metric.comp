#version 450
// depth_to_metric: raw sensor depth (uint16 units) → metric depth along the optical axis, corrected for
// the sensor's inverse-depth bias (1/z = 1/z_raw − b) and gated to the sensor's trusted range.
//
// Bindings (set 0, std430 storage buffers, images row-major and tightly packed, width × height):
//   0  raw_words  readonly   uint[]   raw depth, two uint16 per word (preprocess/packing.glsl)
//   1  depth_m    writeonly  float[]  metric depth [m], 0 = invalid
// Push constants: DepthToMetricParams (vifusion/preprocess/kernel_params.hpp).
// CPU reference: depthToMetricCpu. One invocation per output pixel.
#extension GL_GOOGLE_include_directive : require
#include "preprocess/packing.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(local_size_x_id = 0, local_size_y_id = 1) in;

layout(push_constant) uniform Params {
  int width;            // [px]
  int height;           // [px]
  float depth_scale_m;  // metres per raw unit
  float min_depth_m;    // smallest kept depth [m], inclusive
  float max_depth_m;    // largest kept depth [m], inclusive
  float inverse_depth_bias_per_m;  // b [1/m]: the sensor's 1/z reads b too high
} params;

layout(set = 0, binding = 0, std430) restrict readonly buffer RawDepth { uint raw_words[]; };
layout(set = 0, binding = 1, std430) restrict writeonly buffer MetricDepth { float depth_m[]; };

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= params.width || pixel.y >= params.height) return;

  // Packing follows the linear pixel index, so odd widths work too (rows may straddle words).
  const uint i = uint(pixel.y * params.width + pixel.x);
  const uint raw = depthOfWord(raw_words[i >> 1u], i);
  const float z_raw_m = float(raw) * params.depth_scale_m;
  const float denominator = 1.0 - params.inverse_depth_bias_per_m * z_raw_m;
  const float z_m = z_raw_m / denominator;
  const bool valid = raw != 0u && denominator > 0.0 && z_m >= params.min_depth_m && z_m <= params.max_depth_m;
  depth_m[i] = valid ? z_m : 0.0;
}
