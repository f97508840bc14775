#version 450
// map_predict_splat: the two atomic passes of model prediction (shaders/include/map/prediction.glsl
// says which surfels are rendered and how a disk is splatted). Compiled twice:
//   VIFUSION_SPLAT_PASS=0 (map_predict_depth): every covered pixel takes the atomicMin of its
//     splatKey (centre pixels first, then the intersection depth).
//   VIFUSION_SPLAT_PASS=1 (map_predict_id): every surfel whose key at a pixel is ≤ that minimum
//     takes the atomicMin of its index, so exact ties go to the lowest index, deterministically.
//     "≤" rather than "==" keeps a pixel covered even if a driver recomputed the depth one ulp
//     lower (the helpers are `precise`, so it should not).
//   VIFUSION_SPLAT_PASS=2 (map_predict_splat64, devices with 64-bit buffer atomics): both at once,
//     atomicMin of (splatKey << 32 | index) in a uint64 per pixel. The smallest packed value has
//     the smallest key and, among equal keys, the lowest index: exactly what the two passes give,
//     in one traversal of the surfels instead of two (the 32-bit passes stay for Mali/V3D).
//
// Bindings (set 0, std430):
//   0  state       readonly   map state: [active_begin or 0, surfel_count) bounds the loop
//   1  params      readonly   PredictionParams (host-written per frame)
//   2  surfels     readonly   Surfel[] of the current ping-pong array
//   3  depth_bits  pass 0: atomicMin target, cleared to 0xffffffff; pass 1: readonly
//   4  ids         pass 1: atomicMin target, cleared to kNoSurfel; pass 0: unused
//   (pass 2: 3 = splat, uint64 per pixel, atomicMin target cleared to all ones; no binding 4)
// Grid-stride over surfels, so the dispatch size is fixed at record time (no indirect dispatch).
// CPU reference: splatModelCpu.
#extension GL_GOOGLE_include_directive : require
#if VIFUSION_SPLAT_PASS == 2
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#endif
#include "map/prediction.glsl"

layout(local_size_x = 128) in;
layout(local_size_x_id = 0) in;

layout(set = 0, binding = 0, std430) restrict readonly buffer MapState {
  uint surfel_count;
  uint overflow_count;
  uint state_frame;
  uint active_begin;
} state;
layout(set = 0, binding = 1, std430) restrict readonly buffer Params { PredictionParams params; };
layout(set = 0, binding = 2, std430) restrict readonly buffer Surfels { Surfel surfels[]; };
#if VIFUSION_SPLAT_PASS == 2
layout(set = 0, binding = 3, std430) restrict buffer Splat { uint64_t splat[]; };
#else
layout(set = 0, binding = 3, std430) restrict buffer DepthBits { uint depth_bits[]; };
layout(set = 0, binding = 4, std430) restrict buffer Ids { uint ids[]; };
#endif

void main() {
  // Loaded once: the compiler may not hoist buffer loads across the atomics in the loop.
  const PredictionParams p = params;
  const uint count = state.surfel_count;
  // The active model lies in [active_begin, surfel_count); the inactive and stable ones anywhere (map_state.glsl).
  const uint first = p.surfels == kPredictActive ? state.active_begin : 0u;
  const uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint i = first + gl_GlobalInvocationID.x; i < count; i += stride) {
    const Surfel surfel = surfels[i];
    if (!isRendered(surfel, p)) continue;
    const CameraSurfel s = toCamera(surfel, p.view);
    if (!(s.p_C.z > p.min_depth_m && s.p_C.z <= p.max_depth_m)) continue;
    const Footprint f = footprintOf(s, p);
    for (int y = f.y0; y <= f.y1; ++y) {
      for (int x = f.x0; x <= f.x1; ++x) {
        vec3 q_C;
        if (!splatPixel(s, ivec2(x, y), p.view, q_C)) continue;
        const uint pixel = uint(y * p.view.width + x);
        const uint bits = splatKey(f, ivec2(x, y), q_C.z);
#if VIFUSION_SPLAT_PASS == 0
        atomicMin(depth_bits[pixel], bits);
#elif VIFUSION_SPLAT_PASS == 2
        atomicMin(splat[pixel], (uint64_t(bits) << 32) | uint64_t(i));
#else
        if (bits <= depth_bits[pixel]) atomicMin(ids[pixel], i);
#endif
      }
    }
  }
}
