#version 450
// map_compact_finish: after the scatter, the scan total becomes the map's surfel count (and the
// `kept` counter of the maintenance stats). One invocation; runs after every reader of the old
// count has finished.
//
// Bindings (set 0, std430): 0 state (surfel_count written), 1 total (uint[1], the last scan
//   level's tile sum), 2 stats.
#extension GL_GOOGLE_include_directive : require
#include "map/cleanup.glsl"

layout(local_size_x = 1) in;

layout(set = 0, binding = 0, std430) restrict buffer MapState {
  uint surfel_count;
  uint overflow_count;
  uint state_frame;
  uint state_pad;
} state;
layout(set = 0, binding = 1, std430) restrict readonly buffer Total { uint total[]; };
layout(set = 0, binding = 2, std430) restrict buffer Stats { VIFUSION_MAINTENANCE_STATS_MEMBERS } stats;

void main() {
  state.surfel_count = total[0];
  stats.kept = total[0];
}
