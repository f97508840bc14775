#version 450
// rgb_to_intensity: RGB888 colour → intensity on the 0..255 scale, as a weighted sum of the channels.
// The default weights (RgbToIntensityParams) are Rec. 601 luma, 0.299 R + 0.587 G + 0.114 B.
// ElasticFusion's grey conversion (0.114·ch0 + 0.299·ch1 + 0.587·ch2, which is luma for neither RGB
// nor BGR order; reference/algorithms.md §1.3) is deliberately not reproduced. The weights are push
// constants so that host and shader cannot disagree, and a BGR source can swap weight_r and weight_b.
//
// Bindings (set 0, std430 storage buffers, images row-major and tightly packed, width × height):
//   0  rgb_words  readonly   uint[]   RGB888, the image's bytes in order (preprocess/packing.glsl)
//   1  intensity  writeonly  float[]  intensity [0..255]
// Push constants: RgbToIntensityParams (vifusion/preprocess/kernel_params.hpp).
// CPU reference: rgbToIntensityCpu. One invocation per output pixel.
#extension GL_GOOGLE_include_directive : require
#include "preprocess/packing.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(local_size_x_id = 0, local_size_y_id = 1) in;

layout(push_constant) uniform Params {
  int width;       // [px]
  int height;      // [px]
  float weight_r;  // weight of the first byte of each pixel
  float weight_g;  // weight of the second byte
  float weight_b;  // weight of the third byte
} params;

layout(set = 0, binding = 0, std430) restrict readonly buffer Rgb { uint rgb_words[]; };
layout(set = 0, binding = 1, std430) restrict writeonly buffer Intensity { float intensity[]; };

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= params.width || pixel.y >= params.height) return;

  const uint i = uint(pixel.y * params.width + pixel.x);
  const uint k = 3u * i;  // byte index of the pixel's first channel
  const float r = float(byteOfWord(rgb_words[k >> 2u], k));
  const float g = float(byteOfWord(rgb_words[(k + 1u) >> 2u], k + 1u));
  const float b = float(byteOfWord(rgb_words[(k + 2u) >> 2u], k + 2u));
  intensity[i] = params.weight_r * r + params.weight_g * g + params.weight_b * b;
}
