// Parameters of map_cleanup.comp, mirrored by vifusion::map::CleanupParams (maintenance_cpu.hpp).
#ifndef VIFUSION_MAP_CLEANUP_GLSL
#define VIFUSION_MAP_CLEANUP_GLSL

#include "map/view.glsl"

struct CleanupParams {
  MapView view;                    // the pose and frame of the index map
  float confidence_threshold;      // stable when confidence ≥ this
  uint time_window_frames;         // δ_t: active when updated within this many frames
  uint unstable_max_age_frames;    // unstable surfels not updated for longer are removed
  float max_depth_m;               // free-space test only for surfels within this depth [m]
  float free_space_margin_m;       // a neighbour must lie this far behind the surfel [m]
  float facing_min_abs_nz;         // and the surfel must face the camera: |n_C.z| > this
  uint free_space_min_neighbours;  // removed when at least this many neighbours agree
  uint full_count;                 // the map is full when surfel_count > this
  float eviction_confidence;       // when full, inactive surfels below this confidence go
  uint eviction_age_frames;        // and when full, inactive surfels not updated for longer go too
  uint pad0, pad1;
};

// Maintenance counters of one frame (MaintenanceStats on the host).
#define VIFUSION_MAINTENANCE_STATS_MEMBERS \
  uint kept;                               \
  uint removed_unstable;                   \
  uint removed_free_space;                 \
  uint evicted_when_full;                  \
  uint retired;

#endif
