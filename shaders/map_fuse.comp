#version 450
// map_fuse: confidence-weighted fusion of the claiming pixel's measurement into each claimed surfel
// (ElasticFusion's update.vert). Exactly one pixel claims a surfel (map_associate: the lowest pixel
// index), so the result does not depend on execution order.
//
// Measurement at pixel (u, v): position p_W = T_W_C·p, normal n_W = R_W_C·n, colour RGB, radius
// r = √2·z/f̄ enlarged by 1/|n_z| (at most 2×), weight α = exp(−γ²/(2σ²))·w_pose(z),
// γ = ‖(u, v) − (cx, cy)‖ / ‖(cx, cy)‖, w_pose = 1 for a frame the dense terms registered and
// σ_z²/(σ_z² + σ_pose²) for one the IMU carried (poseWeight in map/fusion_params.glsl). With c the
// surfel's confidence:
//   if r < radius_update_ratio · r_surfel: position, normal (renormalised), colour and radius
//     become (c·old + α·new)/(c + α);
//   always: confidence c + α, last update = frame.
// (A much larger footprint than the surfel's is a coarser view of it: it confirms the surfel but
// would blur its geometry.)
//
// Bindings (set 0, std430):
//   0  vertices      readonly  vec4[w·h]  camera frame [m]
//   1  normals       readonly  vec4[w·h]  camera frame
//   2  rgb_words     readonly  uint[]     packed RGB888 (preprocess/packing.glsl)
//   3  params        readonly  FusionParams
//   4  state         readonly  MapState   surfel_count, active_begin
//   5  surfel_claim  readonly  uint[capacity]  claiming pixel index, kUnclaimed = none
//   6  surfels                 Surfel[capacity]  current surfel array
// One invocation per surfel, grid-stride over [active_begin, surfel_count) (only active surfels are
// claimed, and the inactive prefix holds none). CPU reference: vifusion::map::fuseCpu.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 256) in;
layout(local_size_x_id = 0) in;

#include "map/fusion_params.glsl"
#include "map/map_state.glsl"
#include "map/surfel.glsl"
#include "preprocess/packing.glsl"

layout(std430, binding = 0) restrict readonly buffer Vertices { vec4 vertices[]; };
layout(std430, binding = 1) restrict readonly buffer Normals { vec4 normals[]; };
layout(std430, binding = 2) restrict readonly buffer Rgb { uint rgb_words[]; };
layout(std430, binding = 3) restrict readonly buffer Params { FusionParams params; };
layout(std430, binding = 4) restrict readonly buffer State { MapState state; };
layout(std430, binding = 5) restrict readonly buffer SurfelClaim { uint surfel_claim[]; };
layout(std430, binding = 6) restrict buffer Surfels { Surfel surfels[]; };

void fuse(uint id, uint pixel_index) {
  const vec4 p = vertices[pixel_index];
  const vec4 n = normals[pixel_index];
  const ivec2 pixel = ivec2(int(pixel_index % uint(params.width)), int(pixel_index / uint(params.width)));
  const float alpha = measurementConfidence(params, pixel, p.z);
  const float radius_m = measurementRadius(params, p.z, n.z);

  Surfel s = surfels[id];
  const float c = s.position_confidence.w;
  if (radius_m < params.radius_update_ratio * s.normal_radius.w) {
    const float w = c + alpha;
    const vec3 p_W = transformPoint(params.T_W_C_rows, p.xyz);
    const vec3 n_W = rotateVector(params.T_W_C_rows, n.xyz);
    const vec3 rgb = FUSION_RGB_OF_PIXEL(rgb_words, pixel_index);
    s.position_confidence.xyz = (c * s.position_confidence.xyz + alpha * p_W) / w;
    const vec3 normal = (c * s.normal_radius.xyz + alpha * n_W) / w;
    const float normal_sq = dot(normal, normal);
    // Opposite normals (possible for grazing surfels) average to nothing: keep the old direction.
    if (normal_sq > 1e-12) s.normal_radius.xyz = normal / sqrt(normal_sq);
    s.normal_radius.w = (c * s.normal_radius.w + alpha * radius_m) / w;
    const vec3 colour = (c * unpackRgb8(floatBitsToUint(s.colour_times.x)) + alpha * rgb) / w;
    s.colour_times.x = uintBitsToFloat(packRgb8(colour));
  }
  s.position_confidence.w = c + alpha;
  s.colour_times.z = float(params.frame);
  surfels[id] = s;
}

void main() {
  const uint count = state.surfel_count;
  const uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint id = state.active_begin + gl_GlobalInvocationID.x; id < count; id += stride) {
    const uint pixel_index = surfel_claim[id];
    if (pixel_index != kUnclaimed) fuse(id, pixel_index);
  }
}
