// The surfel record shared by every map kernel (mirrored by vifusion::map::Surfel in
// pipeline/map/include/vifusion/map/surfel.hpp). Three vec4, 48 bytes, std430:
//   position_confidence  xyz position in the map world W [m], w confidence (accumulated weight)
//   normal_radius        xyz unit normal in W, w radius [m]
//   colour_times         x RGB8 packed as uint (floatBitsToUint), y frame of creation,
//                        z frame of last update, w unused (0)
// Frame numbers are stored as floats: exact up to 2^24 frames (155 hours at 30 Hz).
// A surfel is "active" when (current frame − last update) ≤ the time window δ_t, "stable" when its
// confidence reaches the confidence threshold.
#ifndef VIFUSION_MAP_SURFEL_GLSL
#define VIFUSION_MAP_SURFEL_GLSL

struct Surfel {
  vec4 position_confidence;
  vec4 normal_radius;
  vec4 colour_times;
};

uint packRgb8(vec3 rgb_0_255) {
  // floor(x + 0.5), not round(): GLSL leaves the direction of halves to the implementation.
  const uvec3 c = uvec3(clamp(floor(rgb_0_255 + 0.5), 0.0, 255.0));
  return c.r | (c.g << 8) | (c.b << 16);
}

vec3 unpackRgb8(uint packed) {
  return vec3(float(packed & 0xffu), float((packed >> 8) & 0xffu), float((packed >> 16) & 0xffu));
}

#endif
