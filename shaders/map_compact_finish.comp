#version 450
// map_compact_finish: after the scatter, the map's new extent: active_begin grows by the retired
// surfels, surfel_count becomes active_begin plus the kept ones (and the `kept` counter of the
// maintenance stats the new count). One invocation; runs after every reader of the old state.
//
// Bindings (set 0, std430): 0 state (surfel_count and active_begin written), 1 kept_total (uint[1],
//   the keep chain's last tile sum), 2 stats, 3 retired_total (uint[1], the retire chain's).
#extension GL_GOOGLE_include_directive : require
#include "map/cleanup.glsl"

layout(local_size_x = 1) in;

layout(set = 0, binding = 0, std430) restrict buffer MapState {
  uint surfel_count;
  uint overflow_count;
  uint state_frame;
  uint active_begin;
} state;
layout(set = 0, binding = 1, std430) restrict readonly buffer KeptTotal { uint kept_total[]; };
layout(set = 0, binding = 2, std430) restrict buffer Stats { VIFUSION_MAINTENANCE_STATS_MEMBERS } stats;
layout(set = 0, binding = 3, std430) restrict readonly buffer RetiredTotal { uint retired_total[]; };

void main() {
  const uint active_begin = state.active_begin + retired_total[0];
  state.active_begin = active_begin;
  state.surfel_count = active_begin + kept_total[0];
  stats.kept = active_begin + kept_total[0];
}
