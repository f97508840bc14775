#version 450
// map_predict_attributes: the resolve pass of model prediction, one invocation per level-0 pixel.
// The winning surfel of the pixel (map_predict_id) is splatted again at this pixel alone and
// writes the camera-frame model maps the tracking terms read:
//   vertex  (x, y, z, z_obs) [m], the ray–plane intersection and the depth the surfel was observed from
//           (observationDepth: what model registration's systematic-error bound reads; > 0, so w ≠ 0
//           still marks a model pixel where reference_fill writes 0)
//   normal  (n, 1), the surfel normal rotated into the camera and flipped to face it (the
//           convention of the preprocessing normal maps)
//   intensity  0.299·R + 0.587·G + 0.114·B of the surfel colour [0..255]
// and vec4(0) / 0 where no surfel won. Per pixel rather than per surfel, so only winners are read.
//
// Bindings (set 0, std430):
//   0  params     readonly   PredictionParams
//   1  surfels    readonly   Surfel[] of the current ping-pong array
//   2  ids        readonly   uint[] winning surfel index per pixel, kNoSurfel = none
//   3  vertices   writeonly  vec4[]
//   4  normals    writeonly  vec4[]
//   5  intensity  writeonly  float[]
// Compiled twice: as above, and with VIFUSION_SPLAT_INT64=1 (map_predict_attributes64) after the
// single 64-bit splat pass, when it reads the packed (key << 32 | id) per pixel from binding 6 and
// also writes the key to depth_bits (binding 7) and the id to ids, so both variants leave the same
// splat images behind.
// CPU reference: resolveModelCpu.
#extension GL_GOOGLE_include_directive : require
#if VIFUSION_SPLAT_INT64
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#endif
#include "map/prediction.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(local_size_x_id = 0, local_size_y_id = 1) in;

layout(set = 0, binding = 0, std430) restrict readonly buffer Params { PredictionParams params; };
layout(set = 0, binding = 1, std430) restrict readonly buffer Surfels { Surfel surfels[]; };
#if VIFUSION_SPLAT_INT64
layout(set = 0, binding = 2, std430) restrict writeonly buffer Ids { uint ids[]; };
layout(set = 0, binding = 6, std430) restrict readonly buffer Splat { uint64_t splat[]; };
layout(set = 0, binding = 7, std430) restrict writeonly buffer DepthBits { uint depth_bits[]; };
#else
layout(set = 0, binding = 2, std430) restrict readonly buffer Ids { uint ids[]; };
#endif
layout(set = 0, binding = 3, std430) restrict writeonly buffer Vertices { vec4 vertices[]; };
layout(set = 0, binding = 4, std430) restrict writeonly buffer Normals { vec4 normals[]; };
layout(set = 0, binding = 5, std430) restrict writeonly buffer Intensity { float intensity[]; };

void main() {
  const PredictionParams p = params;
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= p.view.width || pixel.y >= p.view.height) return;
  const uint index = uint(pixel.y * p.view.width + pixel.x);

#if VIFUSION_SPLAT_INT64
  const uint64_t packed = splat[index];
  const uint id = uint(packed & 0xffffffffUL);
  ids[index] = id;
  depth_bits[index] = uint(packed >> 32);
#else
  const uint id = ids[index];
#endif
  if (id == kNoSurfel) {
    vertices[index] = vec4(0.0);
    normals[index] = vec4(0.0);
    intensity[index] = 0.0;
    return;
  }
  const Surfel surfel = surfels[id];
  const CameraSurfel s = toCamera(surfel, p.view);
  vec3 q_C;
  splatPixel(s, pixel, p.view, q_C);  // the winner covered this pixel in the splat passes
  precise float n_dot_q = (s.n_C.x * q_C.x + s.n_C.y * q_C.y) + s.n_C.z * q_C.z;
  const vec3 n_C = n_dot_q > 0.0 ? -s.n_C : s.n_C;
  const vec3 rgb = unpackRgb8(floatBitsToUint(surfel.colour_times.x));
  precise float grey = (0.299 * rgb.r + 0.587 * rgb.g) + 0.114 * rgb.b;

  vertices[index] = vec4(q_C, observationDepth(surfel, p.view));
  normals[index] = vec4(n_C, 1.0);
  intensity[index] = grey;
}
