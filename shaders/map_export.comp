#version 450
// map_export: copies one chunk of the current ping-pong surfel array, surfels [first_surfel,
// first_surfel + n) with n = min(chunk_surfels, surfel_count − first_surfel) (0 past the end), to
// the front of a small host-readable staging buffer. The host writes first_surfel, runs the
// recorded dispatch and copies the chunk out, chunk after chunk (pipeline/map map_export.hpp),
// so reading a 2 M-surfel map never needs a map-sized readback buffer. surfel_count is read here,
// on the GPU, so nothing beyond the live surfels is ever copied.
//
// Surfels (include/map/surfel.glsl, 48 bytes) are copied as three uvec4 of raw words: the export
// is bit for bit whatever the floats hold (NaN payloads, denormals).
//
// Bindings (set 0, std430):
//   0  state    readonly   map state: surfel_count
//   1  params   readonly   ExportParams (host-written before each chunk)
//   2  source   readonly   current surfel array, 3 uvec4 per surfel
//   3  staging  writeonly  chunk_surfels surfels, 3 uvec4 each; entries from n on are not written
// Grid-stride over the chunk. CPU reference: exportChunkCpu (pipeline/map export_cpu.hpp).

layout(local_size_x = 128) in;
layout(local_size_x_id = 0) in;

layout(set = 0, binding = 0, std430) restrict readonly buffer MapState {
  uint surfel_count;
  uint overflow_count;
  uint state_frame;
  uint active_begin;
} state;
layout(set = 0, binding = 1, std430) restrict readonly buffer ExportParams {
  uint first_surfel;
  uint chunk_surfels;
  uint params_pad0;
  uint params_pad1;
} params;
layout(set = 0, binding = 2, std430) restrict readonly buffer Source { uvec4 source[]; };
layout(set = 0, binding = 3, std430) restrict writeonly buffer Staging { uvec4 staging[]; };

const uint kWordsPerSurfel = 3u;  // uvec4 per surfel

void main() {
  const uint count = state.surfel_count;
  const uint first = params.first_surfel;
  // count − first, not first + chunk: no overflow; word indices stay below 3·2^26 (max capacity).
  const uint n = first < count ? min(params.chunk_surfels, count - first) : 0u;
  const uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint i = gl_GlobalInvocationID.x; i < n; i += stride) {
    const uint from = (first + i) * kWordsPerSurfel;
    const uint to = i * kWordsPerSurfel;
    staging[to] = source[from];
    staging[to + 1u] = source[from + 1u];
    staging[to + 2u] = source[from + 2u];
  }
}
