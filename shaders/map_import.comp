#version 450
// map_import: writes one chunk of a loaded map into the current ping-pong surfel array: surfels
// [first_surfel, first_surfel + count) from the front of a small host-written staging buffer. The host
// fills the staging buffer from the map file, writes first_surfel and count, and runs the recorded
// dispatch, chunk after chunk (pipeline/map map_import.hpp), so loading a 2 M-surfel map never needs a
// map-sized upload buffer; then it sets the map state. The host keeps first_surfel + count ≤ capacity.
//
// Surfels (include/map/surfel.glsl, 48 bytes) are copied as three uvec4 of raw words: the import is bit
// for bit whatever the file's floats hold (the colour's RGB8 bits, NaN payloads).
//
// Bindings (set 0, std430):
//   0  params       readonly   ImportParams (host-written before each chunk)
//   1  staging      readonly   count surfels, 3 uvec4 each
//   2  destination  writeonly  current surfel array, 3 uvec4 per surfel; entries outside the chunk untouched
// Grid-stride over the chunk. CPU reference: importChunkCpu (pipeline/map import_cpu.hpp).

layout(local_size_x = 128) in;
layout(local_size_x_id = 0) in;

layout(set = 0, binding = 0, std430) restrict readonly buffer ImportParams {
  uint first_surfel;
  uint count;
  uint params_pad0;
  uint params_pad1;
} params;
layout(set = 0, binding = 1, std430) restrict readonly buffer Staging { uvec4 staging[]; };
layout(set = 0, binding = 2, std430) restrict writeonly buffer Destination { uvec4 destination[]; };

const uint kWordsPerSurfel = 3u;  // uvec4 per surfel

void main() {
  const uint n = params.count;
  const uint first = params.first_surfel;
  const uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint i = gl_GlobalInvocationID.x; i < n; i += stride) {
    const uint from = i * kWordsPerSurfel;
    const uint to = (first + i) * kWordsPerSurfel;
    destination[to] = staging[from];
    destination[to + 1u] = staging[from + 1u];
    destination[to + 2u] = staging[from + 2u];
  }
}
