#version 450
// map_compact_add: makes one level's tile-local offsets global by adding the (already global)
// offset of their tile from the level above: offsets[i] += tile_offsets[i / kCompactTileSize].
//
// Bindings (set 0, std430): 0 state (readonly), 1 offsets (this level, read-write),
//   2 tile_offsets (the level above, readonly).
// Push constants: the level (≥ 1). Grid-stride over the level's elements.
#extension GL_GOOGLE_include_directive : require
#include "map/compact.glsl"

layout(local_size_x = 128) in;
layout(local_size_x_id = 0) in;

layout(push_constant) uniform Push { uint level; } push;

layout(set = 0, binding = 0, std430) restrict readonly buffer MapState {
  uint surfel_count;
  uint overflow_count;
  uint state_frame;
  uint active_begin;
} state;
layout(set = 0, binding = 1, std430) restrict buffer Offsets { uint offsets[]; };
layout(set = 0, binding = 2, std430) restrict readonly buffer TileOffsets { uint tile_offsets[]; };

void main() {
  const uint n = compactLevelCount(state.surfel_count - state.active_begin, push.level);
  const uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint i = gl_GlobalInvocationID.x; i < n; i += stride) offsets[i] += tile_offsets[i / kCompactTileSize];
}
