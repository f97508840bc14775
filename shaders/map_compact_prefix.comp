#version 450
// map_compact_prefix: after the scatter, copies the surfels it retired, [begin, begin + retired_total)
// of the other array, back into the same places of the current array, so that the inactive prefix
// [0, active_begin) stays identical in both ping-pong arrays (map_state.glsl) and is never copied as a
// whole. What else the current array holds past the prefix is stale: the next compaction writes it.
//
// Bindings (set 0, std430):
//   0  state          readonly   map state: active_begin (before compaction)
//   1  retired_total  readonly   uint[1]
//   2  compacted      readonly   Surfel[] the other array, just written by map_compact_scatter
//   3  previous       writeonly  Surfel[] the current array
// Grid-stride over the retired surfels. CPU reference: compactCpu (both arrays end with the same prefix).
#extension GL_GOOGLE_include_directive : require
#include "map/surfel.glsl"

layout(local_size_x = 128) in;
layout(local_size_x_id = 0) in;

layout(set = 0, binding = 0, std430) restrict readonly buffer MapState {
  uint surfel_count;
  uint overflow_count;
  uint state_frame;
  uint active_begin;
} state;
layout(set = 0, binding = 1, std430) restrict readonly buffer RetiredTotal { uint retired_total[]; };
layout(set = 0, binding = 2, std430) restrict readonly buffer Compacted { Surfel compacted[]; };
layout(set = 0, binding = 3, std430) restrict writeonly buffer Previous { Surfel previous[]; };

void main() {
  const uint begin = state.active_begin;
  const uint retired = retired_total[0];
  const uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint k = gl_GlobalInvocationID.x; k < retired; k += stride) previous[begin + k] = compacted[begin + k];
}
