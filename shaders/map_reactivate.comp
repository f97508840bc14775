#version 450
// map_reactivate: after a local loop closure has deformed the active map onto the inactive one, the inactive
// surfels the camera sees again become active (ElasticFusion's reactivation): the ones that won a pixel of the
// inactive model's prediction at the current pose get last-update frame = the current frame, so tracking
// and fusion use and refine them from the next frame on, and the revisited surfaces are not mapped a second
// time beside them. Several pixels may name one surfel; they all write the same value.
//
// Bindings (set 0, std430):
//   0  state    readonly  map state: surfel_count (ids at or beyond it are ignored)
//   1  surfels            the surfel array the inactive prediction rendered (include/map/surfel.glsl)
//   2  ids      readonly  the inactive prediction's level-0 splat ids, uint per pixel, 0xffffffff = none
//   3  params   readonly  ReactivateParams: pixel count, frame
// One invocation per pixel (grid-stride). CPU reference: vifusion::map::reactivateSurfelsCpu.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 128) in;
layout(local_size_x_id = 0) in;

#include "map/surfel.glsl"

layout(set = 0, binding = 0, std430) restrict readonly buffer MapState {
  uint surfel_count;
  uint overflow_count;
  uint state_frame;
  uint active_begin;
} state;
layout(set = 0, binding = 1, std430) restrict buffer Surfels { Surfel surfels[]; };
layout(set = 0, binding = 2, std430) restrict readonly buffer Ids { uint ids[]; };
layout(set = 0, binding = 3, std430) restrict readonly buffer ReactivateParams {
  uint pixel_count;  // level-0 pixels of the id image
  uint frame;        // the current frame: the reactivated surfels' last update
  uint params_pad0;
  uint params_pad1;
} params;

void main() {
  const uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint pixel = gl_GlobalInvocationID.x; pixel < params.pixel_count; pixel += stride) {
    const uint id = ids[pixel];
    if (id < state.surfel_count) surfels[id].colour_times.z = float(params.frame);
  }
}
