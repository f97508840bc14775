#version 450
// map_compact_scatter: copies every kept surfel of the current ping-pong array to its global
// offset in the other array. Offsets come from an exclusive scan, so kept surfels keep their
// relative order (a stable compaction: same map, same result, on every device).
//
// Bindings (set 0, std430):
//   0  state         readonly   map state: surfel_count (before compaction)
//   1  keep          readonly   uint[] keep flags (0/1)
//   2  offsets       readonly   uint[] tile-local exclusive offsets (level 0)
//   3  tile_offsets  readonly   uint[] global exclusive offsets of the tiles (level 1)
//   4  source        readonly   Surfel[] current array
//   5  destination   writeonly  Surfel[] the other array
// Grid-stride over surfels. CPU reference: compactCpu.
#extension GL_GOOGLE_include_directive : require
#include "map/compact.glsl"
#include "map/surfel.glsl"

layout(local_size_x = 128) in;
layout(local_size_x_id = 0) in;

layout(set = 0, binding = 0, std430) restrict readonly buffer MapState {
  uint surfel_count;
  uint overflow_count;
  uint state_frame;
  uint state_pad;
} state;
layout(set = 0, binding = 1, std430) restrict readonly buffer Keep { uint keep[]; };
layout(set = 0, binding = 2, std430) restrict readonly buffer Offsets { uint offsets[]; };
layout(set = 0, binding = 3, std430) restrict readonly buffer TileOffsets { uint tile_offsets[]; };
layout(set = 0, binding = 4, std430) restrict readonly buffer Source { Surfel source[]; };
layout(set = 0, binding = 5, std430) restrict writeonly buffer Destination { Surfel destination[]; };

void main() {
  const uint count = state.surfel_count;
  const uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint i = gl_GlobalInvocationID.x; i < count; i += stride) {
    if (keep[i] == 0u) continue;
    destination[offsets[i] + tile_offsets[i / kCompactTileSize]] = source[i];
  }
}
