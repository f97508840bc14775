#version 450
// map_compact_scan: exclusive prefix sum of one level of the compaction (include/map/compact.glsl),
// one tile per workgroup iteration: each invocation scans 4 consecutive values serially, the
// workgroup scans the invocation totals in shared memory (Hillis–Steele, log2(workgroup) steps),
// and the tile's total goes to the next level. Shared memory and barriers only: no subgroup
// operations, no 64-bit atomics.
//
// Bindings (set 0, std430):
//   0  state      readonly   map state: surfel_count − active_begin (the visited range) sizes every level
//   1  values     readonly   uint[] this level's input (keep flags at level 0)
//   2  offsets    writeonly  uint[] tile-local exclusive prefix sums of `values`
//   3  tile_sums  writeonly  uint[] the next level's input: one total per tile
// Push constants: the level. Spec constant 3: kCompactTileSize = 4 × workgroup size.
// CPU reference: exclusiveScanCpu (the levels together give the global exclusive scan).
#extension GL_GOOGLE_include_directive : require
#include "map/compact.glsl"

layout(local_size_x = 256) in;
layout(local_size_x_id = 0) in;

const uint kItemsPerInvocation = 4u;

layout(push_constant) uniform Push { uint level; } push;

layout(set = 0, binding = 0, std430) restrict readonly buffer MapState {
  uint surfel_count;
  uint overflow_count;
  uint state_frame;
  uint active_begin;
} state;
layout(set = 0, binding = 1, std430) restrict readonly buffer Values { uint values[]; };
layout(set = 0, binding = 2, std430) restrict writeonly buffer Offsets { uint offsets[]; };
layout(set = 0, binding = 3, std430) restrict writeonly buffer TileSums { uint tile_sums[]; };

shared uint partial[2][gl_WorkGroupSize.x];

void main() {
  const uint n = compactLevelCount(state.surfel_count - state.active_begin, push.level);
  const uint tiles = compactTiles(n);
  const uint lane = gl_LocalInvocationID.x;
  const uint lanes = gl_WorkGroupSize.x;
  // `tile` is uniform across the workgroup, so every barrier below is in uniform control flow.
  for (uint tile = gl_WorkGroupID.x; tile < tiles; tile += gl_NumWorkGroups.x) {
    const uint first = tile * kCompactTileSize + lane * kItemsPerInvocation;
    uint v[kItemsPerInvocation];
    uint total = 0u;
    for (uint k = 0u; k < kItemsPerInvocation; ++k) {
      v[k] = first + k < n ? values[first + k] : 0u;
      total += v[k];
    }
    partial[0][lane] = total;
    barrier();
    uint source = 0u;
    for (uint shift = 1u; shift < lanes; shift <<= 1u) {
      uint sum = partial[source][lane];
      if (lane >= shift) sum += partial[source][lane - shift];
      partial[1u - source][lane] = sum;
      source = 1u - source;
      barrier();
    }
    uint running = partial[source][lane] - total;  // exclusive prefix of this invocation
    for (uint k = 0u; k < kItemsPerInvocation; ++k) {
      if (first + k < n) offsets[first + k] = running;
      running += v[k];
    }
    if (lane == lanes - 1u) tile_sums[tile] = partial[source][lane];
    barrier();  // the next tile overwrites `partial`
  }
}
