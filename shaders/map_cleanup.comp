#version 450
// map_cleanup: for each surfel of the visited range [active_begin, surfel_count) (map_state.glsl), a keep
// flag (1: stays in the active range) and a retire flag (1: moves to the inactive prefix), both 0 when it
// is removed: the inputs of the compaction. A pure function of the map, the index map and the frame
// number, checked in this order:
//   1. INACTIVE (not updated within δ_t): retired — they are the loop-closure memory — unless
//      the map is full (surfel_count > full_count, 0.95·capacity) and the surfel's confidence is
//      below eviction_confidence or it was last updated more than eviction_age_frames ago: then
//      it is evicted (never-stable memory first, then the oldest; MapMaintenance sets the age).
//   2. UNSTABLE (confidence < threshold) and not updated for more than unstable_max_age frames:
//      removed (a one-off measurement that nothing confirmed).
//   3. FREE-SPACE VIOLATION: an active surfel in view (0 < z ≤ max depth), facing the camera
//      (|n_C.z| > facing_min_abs_nz), whose 3×3 index-map neighbourhood at its projected pixel
//      holds ≥ free_space_min_neighbours entries that are other STABLE surfels UPDATED THIS FRAME
//      lying more than free_space_margin_m behind it: this frame saw through it. Removed.
//      (ElasticFusion's rule with its 1 cm margin, 0.85 facing test and "> 4 neighbours", on a
//      level-0 index map instead of a 4× super-sampled one.)
// Removals are counted with 32-bit atomicAdd; sums do not depend on the order.
//
// Bindings (set 0, std430):
//   0  state        readonly   map state: surfel_count, active_begin
//   1  params       readonly   CleanupParams (host-written per frame)
//   2  surfels      readonly   Surfel[] of the current ping-pong array
//   3  index_depth  readonly   uint[] floatBitsToUint of the nearest surfel's camera depth [m]
//   4  index_id     readonly   uint[] surfel index + 1 of that surfel, 0 = none
//   5  keep         writeonly  uint[] per visited surfel i, at i − active_begin: 1 stays active, else 0
//   6  stats        atomic counters (zeroed before the dispatch)
//   7  retire       writeonly  uint[] per visited surfel, at i − active_begin: 1 moves to the inactive prefix
// Grid-stride over the visited range. CPU reference: cleanupCpu.
#extension GL_GOOGLE_include_directive : require
#include "map/surfel.glsl"
#include "map/cleanup.glsl"

layout(local_size_x = 128) in;
layout(local_size_x_id = 0) in;

layout(set = 0, binding = 0, std430) restrict readonly buffer MapState {
  uint surfel_count;
  uint overflow_count;
  uint state_frame;
  uint active_begin;
} state;
layout(set = 0, binding = 1, std430) restrict readonly buffer Params { CleanupParams params; };
layout(set = 0, binding = 2, std430) restrict readonly buffer Surfels { Surfel surfels[]; };
layout(set = 0, binding = 3, std430) restrict readonly buffer IndexDepth { uint index_depth[]; };
layout(set = 0, binding = 4, std430) restrict readonly buffer IndexId { uint index_id[]; };
layout(set = 0, binding = 5, std430) restrict writeonly buffer Keep { uint keep[]; };
layout(set = 0, binding = 6, std430) restrict buffer Stats { VIFUSION_MAINTENANCE_STATS_MEMBERS } stats;
layout(set = 0, binding = 7, std430) restrict writeonly buffer Retire { uint retire[]; };

bool violatesFreeSpace(uint i, Surfel surfel, uint count, CleanupParams p) {
  const MapView view = p.view;
  const vec3 p_C = transformPoint(view, surfel.position_confidence.xyz);
  if (!(p_C.z > 0.0 && p_C.z <= p.max_depth_m)) return false;
  const vec3 n_C = rotateVector(view, surfel.normal_radius.xyz);
  if (!(abs(n_C.z) > p.facing_min_abs_nz)) return false;
  precise vec2 centre = floor(projectPoint(view, p_C) + 0.5);
  if (!(centre.x >= 0.0 && centre.x < float(view.width) && centre.y >= 0.0 && centre.y < float(view.height))) {
    return false;
  }
  const ivec2 pixel = ivec2(centre);
  uint behind = 0u;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      const ivec2 q = pixel + ivec2(dx, dy);
      if (q.x < 0 || q.y < 0 || q.x >= view.width || q.y >= view.height) continue;
      const uint index = uint(q.y * view.width + q.x);
      const uint id = index_id[index];
      if (id == 0u || id - 1u == i || id - 1u >= count) continue;
      const Surfel other = surfels[id - 1u];
      if (other.position_confidence.w < p.confidence_threshold) continue;
      if (uint(other.colour_times.z) != view.frame) continue;
      precise float gap_m = uintBitsToFloat(index_depth[index]) - p_C.z;
      if (gap_m > p.free_space_margin_m) ++behind;
    }
  }
  return behind >= p.free_space_min_neighbours;
}

void main() {
  // Loaded once: the compiler may not hoist buffer loads across the atomics in the loop.
  const CleanupParams p = params;
  const uint count = state.surfel_count;
  const uint begin = state.active_begin;
  const uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint i = begin + gl_GlobalInvocationID.x; i < count; i += stride) {
    const Surfel surfel = surfels[i];
    const float confidence = surfel.position_confidence.w;
    const uint age = framesSince(p.view, surfel.colour_times.z);
    uint flag = 1u;
    uint retired = 0u;
    if (age > p.time_window_frames) {
      flag = 0u;
      if (count > p.full_count && (confidence < p.eviction_confidence || age > p.eviction_age_frames)) {
        atomicAdd(stats.evicted_when_full, 1u);
      } else {
        retired = 1u;
        atomicAdd(stats.retired, 1u);
      }
    } else if (confidence < p.confidence_threshold && age > p.unstable_max_age_frames) {
      flag = 0u;
      atomicAdd(stats.removed_unstable, 1u);
    } else if (violatesFreeSpace(i, surfel, count, p)) {
      flag = 0u;
      atomicAdd(stats.removed_free_space, 1u);
    }
    keep[i - begin] = flag;
    retire[i - begin] = retired;
  }
}
