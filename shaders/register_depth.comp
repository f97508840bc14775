#version 450
// register_depth: raw depth of the depth camera D → raw depth in the pixels of the colour camera C
// (same units), by forward warping: every valid depth pixel (u, v) with raw depth d goes to
// h = d·(H·(u, v, 1)) + e (H = K_C·R_C_D·K_D⁻¹, e = K_C·t_C_D / depth_scale, both in the push
// constants), lands on the nearest colour pixel of (h_x/h_z, h_y/h_z) with depth round(h_z), and the
// nearest surface wins. Nothing is splatted: colour pixels nothing lands on stay 0 (the reasons are in
// vifusion/preprocess/depth_registration.hpp).
//
// Two passes over a uint z-buffer, one per colour pixel, which the host fills with kEmptyZ first:
//   VIFUSION_REGISTER_PASS 0, scatter: one invocation per depth pixel, atomicMin(zbuffer, depth).
//     The minimum is order-independent, so the result does not depend on scheduling. (One pass
//     straight into the packed output is not possible: two uint16 pixels share a word, and there is
//     no 16-bit atomicMin without optional features.)
//   VIFUSION_REGISTER_PASS 1, resolve: one invocation per output word (two colour pixels), kEmptyZ → 0,
//     packed like the uploaded depth (preprocess/packing.glsl), so depth_to_metric reads it unchanged.
//
// Bindings (set 0, std430 storage buffers, images row-major and tightly packed):
//   pass 0:  0  raw_words         readonly   uint[]  raw depth, depth_width × depth_height, two uint16 per word
//            1  zbuffer           read-write uint[]  one per colour pixel [units], kEmptyZ = nothing landed
//   pass 1:  0  zbuffer           readonly   uint[]  as above
//            1  registered_words  writeonly  uint[]  raw depth, colour_width × colour_height, two per word, 0 = none
// Push constants: RegisterDepthParams (vifusion/preprocess/kernel_params.hpp).
// CPU reference: registerDepthCpu, bit for bit: every a·b + c below is `precise` (no FMA, as the
// reference is compiled with -ffp-contract=off), + and · are correctly rounded in Vulkan, and the one
// division only proposes a pixel that nearestPixel's exact comparisons confirm or move by one.
#extension GL_GOOGLE_include_directive : require
#include "preprocess/packing.glsl"

#ifndef VIFUSION_REGISTER_PASS
#error "define VIFUSION_REGISTER_PASS: 0 = scatter, 1 = resolve"
#endif

layout(local_size_x = 16, local_size_y = 16) in;
layout(local_size_x_id = 0, local_size_y_id = 1) in;

layout(push_constant) uniform Params {
  int depth_width;    // input width [px]
  int depth_height;   // input height [px]
  int colour_width;   // output width [px], even
  int colour_height;  // output height [px]
  float h00, h01, h02;  // H = K_C·R_C_D·K_D⁻¹, row 0 [1, 1, px]
  float h10, h11, h12;  // row 1 [1, 1, px]
  float h20, h21, h22;  // row 2 [1/px, 1/px, 1]
  float e_x, e_y, e_z;  // K_C·t_C_D / depth_scale [units·px, units·px, units]
} params;

// Empty z-buffer entry: above every depth, so atomicMin replaces it; the host fills it each frame.
const uint kEmptyZ = 0xFFFFFFFFu;

#if VIFUSION_REGISTER_PASS == 0

layout(set = 0, binding = 0, std430) restrict readonly buffer RawDepth { uint raw_words[]; };
layout(set = 0, binding = 1, std430) restrict buffer ZBuffer { uint zbuffer[]; };

// Largest raw depth an output pixel can hold [units] (uint16).
const float kMaxRawDepth = 65535.0;

// The colour pixel index along one axis: the largest k with fl((k − ½)·h_z) ≤ h (round half up,
// decided by correctly rounded products), −1 outside 0..size−1. h / h_z (≤ 2.5 ulp here, exact on the
// CPU) only proposes k; the comparisons move it by one where it fell on the wrong side. The guard
// sits at integers, far from the half-integer boundaries, so it cannot make devices disagree.
int nearestPixel(float h, float h_z, int size) {
  const float q = h / h_z;
  if (!(q > -1.0 && q < float(size))) return -1;
  int k = int(floor(q + 0.5));
  precise const float lower = (float(k) - 0.5) * h_z;
  precise const float upper = (float(k) + 0.5) * h_z;
  if (h < lower) {
    k -= 1;
  } else if (h >= upper) {
    k += 1;
  }
  return k >= 0 && k < size ? k : -1;
}

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= params.depth_width || pixel.y >= params.depth_height) return;

  const uint i = uint(pixel.y * params.depth_width + pixel.x);
  const uint raw = depthOfWord(raw_words[i >> 1u], i);
  if (raw == 0u) return;
  const float u = float(pixel.x);
  const float v = float(pixel.y);
  const float d = float(raw);
  precise const float ray_x = params.h00 * u + params.h01 * v + params.h02;
  precise const float ray_y = params.h10 * u + params.h11 * v + params.h12;
  precise const float ray_z = params.h20 * u + params.h21 * v + params.h22;
  precise const float h_x = d * ray_x + params.e_x;
  precise const float h_y = d * ray_y + params.e_y;
  precise const float h_z = d * ray_z + params.e_z;
  // Behind or at the colour camera, or beyond uint16: dropped. h_z ≥ ½ keeps the rounded depth ≥ 1.
  if (!(h_z >= 0.5 && h_z < kMaxRawDepth + 0.5)) return;
  const int x = nearestPixel(h_x, h_z, params.colour_width);
  const int y = nearestPixel(h_y, h_z, params.colour_height);
  if (x < 0 || y < 0) return;
  precise const float z_units = floor(h_z + 0.5);
  atomicMin(zbuffer[y * params.colour_width + x], uint(z_units));
}

#else

layout(set = 0, binding = 0, std430) restrict readonly buffer ZBuffer { uint zbuffer[]; };
layout(set = 0, binding = 1, std430) restrict writeonly buffer Registered { uint registered_words[]; };

uint rawOfZ(uint z) { return z == kEmptyZ ? 0u : z; }

void main() {
  // Word (x, y) holds colour pixels (2x, y) and (2x + 1, y): the width is even, so no word straddles rows.
  const ivec2 word = ivec2(gl_GlobalInvocationID.xy);
  const int words_per_row = params.colour_width / 2;
  if (word.x >= words_per_row || word.y >= params.colour_height) return;

  const int first = word.y * params.colour_width + 2 * word.x;
  registered_words[word.y * words_per_row + word.x] = rawOfZ(zbuffer[first]) | (rawOfZ(zbuffer[first + 1]) << 16u);
}

#endif
