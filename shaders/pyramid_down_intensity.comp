#version 450
// pyramid_down_intensity: halves an intensity image for the next pyramid level. Output pixel (x, y)
// is the separable 5-tap Gaussian (preprocess/common.glsl) centred on input pixel (2x, 2y), with
// coordinates clamped to the image (border replicate). The weights sum to 1, so no normalisation.
//
// Bindings (set 0, std430 storage buffers, images row-major and tightly packed):
//   0  fine    readonly   float[]  intensity [0..255], src_width × src_height
//   1  coarse  writeonly  float[]  intensity [0..255], (src_width/2) × (src_height/2) (floor)
// Push constants: PyramidDownIntensityParams (vifusion/preprocess/kernel_params.hpp).
// CPU reference: pyramidDownIntensityCpu. One invocation per output (coarse) pixel.
#extension GL_GOOGLE_include_directive : require
#include "preprocess/common.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(local_size_x_id = 0, local_size_y_id = 1) in;

layout(push_constant) uniform Params {
  int src_width;   // fine width [px]
  int src_height;  // fine height [px]
} params;

layout(set = 0, binding = 0, std430) restrict readonly buffer Fine { float fine[]; };
layout(set = 0, binding = 1, std430) restrict writeonly buffer Coarse { float coarse[]; };

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  const int dst_width = params.src_width / 2;
  if (pixel.x >= dst_width || pixel.y >= params.src_height / 2) return;

  const ivec2 centre = 2 * pixel;
  float sum = 0.0;
  for (int dy = -2; dy <= 2; ++dy) {
    const int y = clamp(centre.y + dy, 0, params.src_height - 1);
    for (int dx = -2; dx <= 2; ++dx) {
      const int x = clamp(centre.x + dx, 0, params.src_width - 1);
      sum += (kPyramidWeights[dx + 2] * kPyramidWeights[dy + 2]) * fine[pixelIndex(ivec2(x, y), params.src_width)];
    }
  }
  coarse[pixelIndex(pixel, dst_width)] = sum;
}
