#version 450
// map_associate: data association of the current frame's pixels with the index map (ElasticFusion's
// data.* shaders, on the pixel's own 3 × 3 window of the index map instead of 4 × 4 half-pixel taps).
//
// Pixel i with camera-frame vertex p and normal n (level-0 maps; needs both valid and z ≤ max depth)
// looks at the surfels of the 3 × 3 index-map window around it. A surfel with camera-frame position
// x and normal m is a candidate when
//   |x.z − p.z| · ‖p‖/p.z < max_depth_diff_m        (depth difference along the pixel ray)
//   m·n > cos(max angle)  or  |m.z| < grazing_normal_z
// and the winner has the smallest distance to the pixel ray, ties to the lower surfel index.
// Both gates and the distance are compared multiplied out (no division, no square root):
//   (x.z − p.z)²·‖p‖² < τ²·p.z²   and   ‖x × p‖² (= distance² · ‖p‖²).
// Output pixel_match[i]: surfel index + 1, kPixelNewSurfel (no candidate), kPixelNoMeasurement.
// A matched pixel claims its surfel with atomicMin(surfel_claim[id], i): the lowest pixel index
// wins, whatever the execution order, and only that pixel updates the surfel (map_fuse).
//
// Bindings (set 0, std430):
//   0  vertices      readonly  vec4[w·h]  (x, y, z, 1) camera frame [m], vec4(0) invalid
//   1  normals       readonly  vec4[w·h]  (n, 1) camera frame, vec4(0) invalid
//   2  surfels       readonly  Surfel[capacity]  current surfel array
//   3  index_id      readonly  uint[w·h]  surfel index + 1, 0 = none
//   4  params        readonly  FusionParams
//   5  pixel_match   writeonly uint[w·h]
//   6  surfel_claim            uint[capacity], kUnclaimed before this kernel
// One invocation per pixel. CPU reference: vifusion::map::associateCpu.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 256) in;
layout(local_size_x_id = 0) in;

#include "map/fusion_params.glsl"
#include "map/surfel.glsl"

layout(std430, binding = 0) restrict readonly buffer Vertices { vec4 vertices[]; };
layout(std430, binding = 1) restrict readonly buffer Normals { vec4 normals[]; };
layout(std430, binding = 2) restrict readonly buffer Surfels { Surfel surfels[]; };
layout(std430, binding = 3) restrict readonly buffer IndexId { uint index_id[]; };
layout(std430, binding = 4) restrict readonly buffer Params { FusionParams params; };
layout(std430, binding = 5) restrict writeonly buffer PixelMatch { uint pixel_match[]; };
layout(std430, binding = 6) restrict buffer SurfelClaim { uint surfel_claim[]; };

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i >= uint(params.width * params.height)) return;
  const vec4 p = vertices[i];
  const vec4 n = normals[i];
  if (!(p.z > 0.0) || p.z > params.max_depth_m || n.w == 0.0) {
    pixel_match[i] = kPixelNoMeasurement;
    return;
  }
  const int u = int(i % uint(params.width));
  const int v = int(i / uint(params.width));
  precise float p_sq = p.x * p.x + p.y * p.y + p.z * p.z;
  precise float depth_gate = params.max_depth_diff_m * params.max_depth_diff_m * p.z * p.z;

  uint best = 0u;  // surfel index + 1
  float best_distance = 0.0;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      const int x = u + dx;
      const int y = v + dy;
      if (x < 0 || x >= params.width || y < 0 || y >= params.height) continue;
      const uint candidate = index_id[y * params.width + x];
      if (candidate == 0u) continue;
      const Surfel s = surfels[candidate - 1u];
      const vec3 x_C = transformPoint(params.T_C_W_rows, s.position_confidence.xyz);
      const vec3 m_C = rotateVector(params.T_C_W_rows, s.normal_radius.xyz);
      precise float dz = x_C.z - p.z;
      precise float depth_term = dz * dz * p_sq;
      if (!(depth_term < depth_gate)) continue;
      precise float normal_cos = m_C.x * n.x + m_C.y * n.y + m_C.z * n.z;
      if (!(normal_cos > params.min_normal_cos) && !(abs(m_C.z) < params.grazing_normal_z)) continue;
      precise float cx = x_C.y * p.z - x_C.z * p.y;
      precise float cy = x_C.z * p.x - x_C.x * p.z;
      precise float cz = x_C.x * p.y - x_C.y * p.x;
      precise float distance = cx * cx + cy * cy + cz * cz;
      if (best == 0u || distance < best_distance || (distance == best_distance && candidate < best)) {
        best = candidate;
        best_distance = distance;
      }
    }
  }
  if (best == 0u) {
    pixel_match[i] = kPixelNewSurfel;
    return;
  }
  pixel_match[i] = best;
  atomicMin(surfel_claim[best - 1u], i);
}
