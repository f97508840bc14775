// The map's state record, shared by every map kernel; mirrored by vifusion::map::MapState
// (pipeline/map/include/vifusion/map/map_buffers.hpp). std430, 16 bytes.
#ifndef VIFUSION_MAP_MAP_STATE_GLSL
#define VIFUSION_MAP_MAP_STATE_GLSL

struct MapState {
  uint surfel_count;    // surfels in the current array, ≤ capacity
  uint overflow_count;  // new surfels dropped since start-up because the map was full
  uint frame;           // frame last fused (written by map_insert)
  // Surfels [0, active_begin) are inactive: the loop-closure memory, which the per-frame passes
  // (index, fusion, active prediction, cleanup, compaction) skip. [active_begin, surfel_count) holds
  // every active surfel and those that turned inactive since the last maintenance. 0 = visit the
  // whole map (map_maintenance.hpp says when the host asks for that).
  uint active_begin;
};

#endif
