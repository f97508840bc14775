#version 450
// intensity_gradient: image gradient by the 3 × 3 Sobel operator divided by 8, so a linear ramp
// I = a·u + b·v gives exactly (a, b) [intensity units per pixel]. Coordinates are clamped to the
// image (border replicate), which halves the gradient across the outermost rows and columns.
//
// Bindings (set 0, std430 storage buffers, images row-major and tightly packed, width × height):
//   0  intensity  readonly   float[]  intensity [0..255]
//   1  gradient   writeonly  vec2[]   (∂I/∂u, ∂I/∂v) [intensity / px]
// Push constants: IntensityGradientParams (vifusion/preprocess/kernel_params.hpp).
// CPU reference: intensityGradientCpu. One invocation per output pixel.
#extension GL_GOOGLE_include_directive : require
#include "preprocess/common.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(local_size_x_id = 0, local_size_y_id = 1) in;

layout(push_constant) uniform Params {
  int width;   // [px]
  int height;  // [px]
} params;

layout(set = 0, binding = 0, std430) restrict readonly buffer Intensity { float intensity[]; };
layout(set = 0, binding = 1, std430) restrict writeonly buffer Gradient { vec2 gradient[]; };

float at(int x, int y) { return intensity[pixelIndex(ivec2(x, y), params.width)]; }

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= params.width || pixel.y >= params.height) return;

  const int x = pixel.x;
  const int y = pixel.y;
  const int xm = max(x - 1, 0);
  const int xp = min(x + 1, params.width - 1);
  const int ym = max(y - 1, 0);
  const int yp = min(y + 1, params.height - 1);
  const float right = at(xp, ym) + 2.0 * at(xp, y) + at(xp, yp);
  const float left = at(xm, ym) + 2.0 * at(xm, y) + at(xm, yp);
  const float below = at(xm, yp) + 2.0 * at(x, yp) + at(xp, yp);
  const float above = at(xm, ym) + 2.0 * at(x, ym) + at(xp, ym);
  // × 0.125 is exact (a power of two), where a GPU division by 8 need not be.
  gradient[pixelIndex(pixel, params.width)] = vec2((right - left) * 0.125, (below - above) * 0.125);
}
