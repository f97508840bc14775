#version 450
// map_reactivate: the inactive surfels the camera sees again become active (ElasticFusion's reactivation, after a
// local loop closure, and per frame in a loaded map): last-update frame = the prediction's frame, so tracking
// and fusion use and refine them from the next pass on, and the revisited surfaces are not mapped a second time
// beside them.
//
// Which: every surfel the inactive prediction renders (prediction.glsl's selection, at its params) whose centre
// projects into a pixel where that prediction's surface passes the fusion association's gates for it
// (map_associate.comp, with the predicted vertex v and normal in place of the measured ones):
//   (s.z − v.z)²·‖v‖² < τ²·v.z²                    (depth difference along the pixel ray below τ)
//   |m·n| > cos(max angle)  or  |m.z| < grazing_normal_z
// i.e. the surfels a measurement at that pixel would be associated with, had they been active — the hidden ones
// behind each pixel's winner included. Fusion associates against an index map of one surfel CENTRE per pixel
// (map_index.comp), so reactivating only the prediction's winners (one per pixel, each disk covering several)
// leaves pixels whose 3 × 3 window holds no active centre, and fusion maps the surface there a second time.
//
// Each reactivated surfel's index is appended to the marked list (the host plans the moves out of the inactive
// prefix from it, planReactivationMoves). At most `capacity` per dispatch: the surfels past it stay inactive
// this time and are taken by the next reactivation that sees them.
//
// Bindings (set 0, std430):
//   0  state     readonly  map state: [0, surfel_count) bounds the loop
//   1  params    readonly  PredictionParams of the inactive prediction (view, frame, selection)
//   2  surfels             the surfel array that prediction rendered (include/map/surfel.glsl)
//   3  vertices  readonly  its level-0 vertex map, vec4 (x, y, z, z_obs) camera frame [m], vec4(0) = no model
//   4  normals   readonly  its level-0 normal map, vec4 (n, 1), vec4(0) = no model
//   5  gates     readonly  ReactivateGates: τ² [m²], cos(max angle), grazing_normal_z, capacity
//   6  count               MarkedCount: indices appended (host-cleared to 0; may pass capacity: the excess is
//                          not marked)
//   7  marked    writeonly the marked surfels' indices, capacity of them
// One invocation per surfel (grid-stride). CPU reference: vifusion::map::reactivateInViewCpu.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 128) in;
layout(local_size_x_id = 0) in;

#include "map/prediction.glsl"

layout(set = 0, binding = 0, std430) restrict readonly buffer MapState {
  uint surfel_count;
  uint overflow_count;
  uint state_frame;
  uint active_begin;
} state;
layout(set = 0, binding = 1, std430) restrict readonly buffer Params { PredictionParams params; };
layout(set = 0, binding = 2, std430) restrict buffer Surfels { Surfel surfels[]; };
layout(set = 0, binding = 3, std430) restrict readonly buffer Vertices { vec4 vertices[]; };
layout(set = 0, binding = 4, std430) restrict readonly buffer Normals { vec4 normals[]; };
layout(set = 0, binding = 5, std430) restrict readonly buffer ReactivateGates {
  float max_depth_diff2_m2;  // τ², τ = FusionOptions::max_depth_diff_m [m²]
  float min_normal_cos;      // cos(FusionOptions::max_normal_angle_rad)
  float grazing_normal_z;    // FusionOptions::grazing_normal_z
  uint capacity;             // most indices one dispatch appends
} gates;
layout(set = 0, binding = 6, std430) restrict buffer MarkedCount { uint marked_count; };
layout(set = 0, binding = 7, std430) restrict writeonly buffer Marked { uint marked[]; };

// True when the predicted surface at the pixel the surfel's centre projects into passes the association gates.
bool onPredictedSurface(CameraSurfel s, MapView view) {
  precise vec2 centre = floor(projectPoint(view, s.p_C) + 0.5);  // footprintOf's centre pixel
  const ivec2 pixel = ivec2(centre);
  if (pixel.x < 0 || pixel.y < 0 || pixel.x >= view.width || pixel.y >= view.height) return false;
  const uint index = uint(pixel.y * view.width + pixel.x);
  const vec4 v = vertices[index];
  if (v.w == 0.0) return false;
  const vec3 n = normals[index].xyz;
  precise float dz = s.p_C.z - v.z;
  precise float v2 = (v.x * v.x + v.y * v.y) + v.z * v.z;
  if (!((dz * dz) * v2 < gates.max_depth_diff2_m2 * (v.z * v.z))) return false;
  precise float cos_angle = abs((s.n_C.x * n.x + s.n_C.y * n.y) + s.n_C.z * n.z);
  return cos_angle > gates.min_normal_cos || abs(s.n_C.z) < gates.grazing_normal_z;
}

void main() {
  const PredictionParams p = params;
  const uint count = state.surfel_count;
  const uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint i = gl_GlobalInvocationID.x; i < count; i += stride) {
    const Surfel surfel = surfels[i];
    if (!isRendered(surfel, p)) continue;
    const CameraSurfel s = toCamera(surfel, p.view);
    if (!(s.p_C.z > p.min_depth_m && s.p_C.z <= p.max_depth_m)) continue;
    if (!onPredictedSurface(s, p.view)) continue;
    const uint slot = atomicAdd(marked_count, 1u);
    if (slot >= gates.capacity) continue;
    marked[slot] = i;
    surfels[i].colour_times.z = float(p.view.frame);
  }
}
