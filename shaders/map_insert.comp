#version 450
// map_insert: new surfels from the pixels map_associate marked kPixelNewSurfel, appended in pixel
// order (row-major) behind the existing surfels. A two-pass prefix sum instead of an atomic counter
// makes the order deterministic: the same frames always give byte-identical surfel arrays.
//   pass 0 (one invocation per pixel):  group_counts[g] = candidates in workgroup g
//   pass 1 (ONE workgroup):             group_counts[g] → surfel_count + candidates before group g
//                                       (in place); surfel_count += candidates, clamped to capacity;
//                                       overflow_count += candidates that did not fit; frame = frame
//   pass 2 (one invocation per pixel):  candidate k of workgroup g becomes surfel group_counts[g] + k,
//                                       written only when that index is < capacity
// A full map stops growing: the candidates beyond capacity are counted, never written (freeing
// space is cleanup's job).
//
// New surfel from pixel (u, v): position T_W_C·p, normal R_W_C·n, radius and confidence α as in
// map_fuse, colour the pixel's RGB, created = updated = frame.
//
// Bindings (set 0, std430):
//   0  vertices      readonly  vec4[w·h]  camera frame [m]
//   1  normals       readonly  vec4[w·h]  camera frame
//   2  rgb_words     readonly  uint[]     packed RGB888
//   3  params        readonly  FusionParams
//   4  pixel_match   readonly  uint[w·h]
//   5  group_counts            uint[ceil(w·h / workgroup size)]
//   6  state                   MapState
//   7  surfels                 Surfel[capacity]  current surfel array
// Push constants: uint pass (0, 1, 2). CPU reference: vifusion::map::insertCpu.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 256) in;
layout(local_size_x_id = 0) in;

#include "map/fusion_params.glsl"
#include "map/map_state.glsl"
#include "map/surfel.glsl"
#include "preprocess/packing.glsl"

layout(push_constant) uniform Push { uint pass; } push;

layout(std430, binding = 0) restrict readonly buffer Vertices { vec4 vertices[]; };
layout(std430, binding = 1) restrict readonly buffer Normals { vec4 normals[]; };
layout(std430, binding = 2) restrict readonly buffer Rgb { uint rgb_words[]; };
layout(std430, binding = 3) restrict readonly buffer Params { FusionParams params; };
layout(std430, binding = 4) restrict readonly buffer PixelMatch { uint pixel_match[]; };
layout(std430, binding = 5) restrict buffer GroupCounts { uint group_counts[]; };
layout(std430, binding = 6) restrict buffer State { MapState state; };
layout(std430, binding = 7) restrict writeonly buffer Surfels { Surfel surfels[]; };

shared uint scan_values[gl_WorkGroupSize.x];

// Exclusive prefix sum of `value` over the workgroup (Hillis–Steele in shared memory: no subgroup
// operations, so it runs on every device); `total` receives the workgroup's sum. Every invocation
// of the workgroup must call it.
uint exclusiveScan(uint value, out uint total) {
  const uint t = gl_LocalInvocationID.x;
  scan_values[t] = value;
  barrier();
  for (uint offset = 1u; offset < gl_WorkGroupSize.x; offset <<= 1) {
    const uint before = t >= offset ? scan_values[t - offset] : 0u;
    barrier();
    scan_values[t] += before;
    barrier();
  }
  total = scan_values[gl_WorkGroupSize.x - 1u];
  return scan_values[t] - value;
}

Surfel newSurfel(uint i) {
  const vec4 p = vertices[i];
  const vec4 n = normals[i];
  const ivec2 pixel = ivec2(int(i % uint(params.width)), int(i / uint(params.width)));
  Surfel s;
  s.position_confidence = vec4(transformPoint(params.T_W_C_rows, p.xyz), measurementConfidence(params, pixel));
  s.normal_radius = vec4(rotateVector(params.T_W_C_rows, n.xyz), measurementRadius(params, p.z, n.z));
  s.colour_times = vec4(uintBitsToFloat(packRgb8(FUSION_RGB_OF_PIXEL(rgb_words, i))), float(params.frame),
                        float(params.frame), 0.0);
  return s;
}

void countCandidates() {
  const uint i = gl_GlobalInvocationID.x;
  const uint pixels = uint(params.width * params.height);
  // A sum needs no scan: the shared atomic gives the same total in any order, with two barriers.
  if (gl_LocalInvocationID.x == 0u) scan_values[0] = 0u;
  barrier();
  if (i < pixels && pixel_match[i] == kPixelNewSurfel) atomicAdd(scan_values[0], 1u);
  barrier();
  if (gl_LocalInvocationID.x == 0u) group_counts[gl_WorkGroupID.x] = scan_values[0];
}

void scanGroups() {
  const uint pixels = uint(params.width * params.height);
  const uint groups = (pixels + gl_WorkGroupSize.x - 1u) / gl_WorkGroupSize.x;
  const uint chunk = (groups + gl_WorkGroupSize.x - 1u) / gl_WorkGroupSize.x;
  const uint first = min(gl_LocalInvocationID.x * chunk, groups);
  const uint last = min(first + chunk, groups);
  const uint base = state.surfel_count;
  uint sum = 0u;
  for (uint g = first; g < last; ++g) sum += group_counts[g];
  uint total;
  uint running = base + exclusiveScan(sum, total);
  for (uint g = first; g < last; ++g) {
    const uint count = group_counts[g];
    group_counts[g] = running;
    running += count;
  }
  if (gl_LocalInvocationID.x == 0u) {
    const uint wanted = base + total;
    const uint kept = min(wanted, params.capacity);
    state.surfel_count = kept;
    state.overflow_count += wanted - kept;
    state.frame = params.frame;
  }
}

void writeSurfels() {
  const uint i = gl_GlobalInvocationID.x;
  const uint pixels = uint(params.width * params.height);
  const bool candidate = i < pixels && pixel_match[i] == kPixelNewSurfel;
  uint total;
  const uint index = group_counts[gl_WorkGroupID.x] + exclusiveScan(candidate ? 1u : 0u, total);
  if (candidate && index < params.capacity) surfels[index] = newSurfel(i);
}

void main() {
  if (push.pass == 0u) {
    countCandidates();
  } else if (push.pass == 1u) {
    scanGroups();
  } else {
    writeSurfels();
  }
}
