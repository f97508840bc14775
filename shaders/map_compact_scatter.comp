#version 450
// map_compact_scatter: moves every surfel of the visited range [begin, surfel_count) of the current
// ping-pong array (begin = active_begin, map_state.glsl) that the cleanup did not remove to its place
// in the other array:
//   retired (inactive now)  → begin + retire_offset(k)              the end of the inactive prefix
//   kept (still active)     → begin + retired_total + keep_offset(k) the new active range
// with k = i − begin and the offsets from exclusive scans, so both groups keep their relative order
// (a stable partition: same map, same result, on every device). The prefix [0, begin) is already
// the same in both arrays (map_compact_prefix keeps it so) and is not touched.
//
// Bindings (set 0, std430):
//   0  state                readonly   map state: surfel_count, active_begin (before compaction)
//   1  keep                 readonly   uint[] keep flags (0/1), per visited surfel
//   2  offsets              readonly   uint[] their tile-local exclusive offsets (level 0)
//   3  tile_offsets         readonly   uint[] global exclusive offsets of the tiles (level 1)
//   4  source               readonly   Surfel[] current array
//   5  destination          writeonly  Surfel[] the other array
//   6  retire               readonly   uint[] retire flags (0/1), per visited surfel
//   7  retire_offsets       readonly   uint[] their tile-local exclusive offsets (level 0)
//   8  retire_tile_offsets  readonly   uint[] global exclusive offsets of their tiles (level 1)
//   9  retired_total        readonly   uint[1] how many are retired
// Grid-stride over the visited range. CPU reference: compactCpu.
#extension GL_GOOGLE_include_directive : require
#include "map/compact.glsl"
#include "map/surfel.glsl"

layout(local_size_x = 128) in;
layout(local_size_x_id = 0) in;

layout(set = 0, binding = 0, std430) restrict readonly buffer MapState {
  uint surfel_count;
  uint overflow_count;
  uint state_frame;
  uint active_begin;
} state;
layout(set = 0, binding = 1, std430) restrict readonly buffer Keep { uint keep[]; };
layout(set = 0, binding = 2, std430) restrict readonly buffer Offsets { uint offsets[]; };
layout(set = 0, binding = 3, std430) restrict readonly buffer TileOffsets { uint tile_offsets[]; };
layout(set = 0, binding = 4, std430) restrict readonly buffer Source { Surfel source[]; };
layout(set = 0, binding = 5, std430) restrict writeonly buffer Destination { Surfel destination[]; };
layout(set = 0, binding = 6, std430) restrict readonly buffer Retire { uint retire[]; };
layout(set = 0, binding = 7, std430) restrict readonly buffer RetireOffsets { uint retire_offsets[]; };
layout(set = 0, binding = 8, std430) restrict readonly buffer RetireTileOffsets { uint retire_tile_offsets[]; };
layout(set = 0, binding = 9, std430) restrict readonly buffer RetiredTotal { uint retired_total[]; };

void main() {
  const uint begin = state.active_begin;
  const uint visited = state.surfel_count - begin;
  const uint active_start = begin + retired_total[0];
  const uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint k = gl_GlobalInvocationID.x; k < visited; k += stride) {
    const uint tile = k / kCompactTileSize;
    if (retire[k] != 0u) {
      destination[begin + retire_offsets[k] + retire_tile_offsets[tile]] = source[begin + k];
    } else if (keep[k] != 0u) {
      destination[active_start + offsets[k] + tile_offsets[tile]] = source[begin + k];
    }
  }
}
