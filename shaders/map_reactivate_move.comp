#version 450
// map_reactivate_move: after map_reactivate has marked the inactive surfels a closure brings back into view,
// the marked ones that lie in the inactive prefix [0, active_begin) move into the active range, so the next
// frame's passes visit them without visiting the whole map (map_buffers.hpp's layout). The host plans the
// moves (vifusion::map::planReactivationMoves): with r marked surfels in the prefix, the prefix shrinks to
// [0, active_begin − r); each marked surfel below that boundary swaps places with an unmarked one inside
// [active_begin − r, active_begin). The pairs are disjoint, so the swaps run in any order. The unmarked
// surfel that moves down stays in the prefix, which must be identical in both surfel arrays: it is written to
// both. The marked one goes to the current array only (the active range of the other array is rewritten by
// the next compaction).
//
// Bindings (set 0, std430):
//   0  current  the surfel array the map lives in (include/map/surfel.glsl)
//   1  other    the other ping-pong array
//   2  moves    readonly  MovePlan: count, then pairs (prefix slot of a marked surfel, slot of an unmarked
//                         surfel in [active_begin − r, active_begin))
// One invocation per move (grid-stride). CPU reference: vifusion::map::applyReactivationMovesCpu.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 128) in;
layout(local_size_x_id = 0) in;

#include "map/surfel.glsl"

layout(set = 0, binding = 0, std430) restrict buffer Current { Surfel current[]; };
layout(set = 0, binding = 1, std430) restrict writeonly buffer Other { Surfel other[]; };
layout(set = 0, binding = 2, std430) restrict readonly buffer MovePlan {
  uint move_count;
  uint plan_pad0;
  uint plan_pad1;
  uint plan_pad2;
  uvec2 moves[];  // x: marked surfel's slot in the shrunk prefix, y: unmarked surfel's slot above it
};

void main() {
  const uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint k = gl_GlobalInvocationID.x; k < move_count; k += stride) {
    const uvec2 move = moves[k];
    const Surfel marked = current[move.x];
    const Surfel unmarked = current[move.y];
    current[move.x] = unmarked;
    other[move.x] = unmarked;
    current[move.y] = marked;
  }
}
