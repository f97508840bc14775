#version 450
// map_insert: new surfels from the pixels map_associate marked kPixelNewSurfel, appended in pixel
// order (row-major) behind the existing surfels. A two-level prefix sum instead of an atomic counter
// makes the order deterministic: the same frames always give byte-identical surfel arrays. The
// pixels are cut into runs of up to kRunPixels consecutive pixels of a row (pixelRun in
// fusion_params.glsl), one invocation per run, and map_associate has already counted each run's
// candidates into run_counts:
//   pass 0 (ONE workgroup):           run_counts[r] → surfel_count + candidates before run r (in
//                                     place); surfel_count += candidates, clamped to capacity;
//                                     overflow_count += candidates that did not fit; frame = frame
//   pass 1 (one invocation per run):  the k-th candidate of run r becomes surfel run_counts[r] + k,
//                                     written only when that index is < capacity
// Runs rather than one pixel per invocation with a workgroup scan: pass 1 needs no shared memory
// and no barrier, and on lavapipe every barrier suspends and resumes each 8-wide slice of the
// workgroup (measured: the workgroup scans were 44 of 434 CPU-ms of a 640×480 frame).
// A full map stops growing: the candidates beyond capacity are counted, never written (freeing
// space is cleanup's job).
//
// New surfel from pixel (u, v): position T_W_C·p, normal R_W_C·n, radius and confidence α (with the
// pose weight) as in map_fuse, colour the pixel's RGB, created = updated = frame.
//
// Bindings (set 0, std430):
//   0  vertices      readonly  vec4[w·h]  camera frame [m]
//   1  normals       readonly  vec4[w·h]  camera frame
//   2  rgb_words     readonly  uint[]     packed RGB888
//   3  params        readonly  FusionParams
//   4  pixel_match   readonly  uint[w·h]
//   5  run_counts              uint[runs]  candidates per run (map_associate), then offsets
//   6  state                   MapState
//   7  surfels                 Surfel[capacity]  current surfel array
// Push constants: uint pass (0, 1). Specialization: 0 = workgroup size, 3 = kRunPixels (the same as
// map_associate's). CPU reference: vifusion::map::insertCpu.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 256) in;
layout(local_size_x_id = 0) in;
layout(constant_id = 3) const uint kRunPixels = 32;

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
layout(std430, binding = 5) restrict buffer RunCounts { uint run_counts[]; };
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
  s.position_confidence = vec4(transformPoint(params.T_W_C_rows, p.xyz), measurementConfidence(params, pixel, p.z));
  s.normal_radius = vec4(rotateVector(params.T_W_C_rows, n.xyz), measurementRadius(params, p.z, n.z));
  s.colour_times = vec4(uintBitsToFloat(packRgb8(FUSION_RGB_OF_PIXEL(rgb_words, i))), float(params.frame),
                        float(params.frame), 0.0);
  return s;
}

void scanRuns() {
  const uint runs = pixelRunCount(params, kRunPixels);
  const uint chunk = (runs + gl_WorkGroupSize.x - 1u) / gl_WorkGroupSize.x;
  const uint first = min(gl_LocalInvocationID.x * chunk, runs);
  const uint last = min(first + chunk, runs);
  const uint base = state.surfel_count;
  uint sum = 0u;
  for (uint r = first; r < last; ++r) sum += run_counts[r];
  uint total;
  uint running = base + exclusiveScan(sum, total);
  for (uint r = first; r < last; ++r) {
    const uint count = run_counts[r];
    run_counts[r] = running;
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
  const uvec3 run = pixelRun(params, kRunPixels, gl_GlobalInvocationID.x);
  if (run.x >= run.y) return;
  uint index = run_counts[gl_GlobalInvocationID.x];
  for (uint i = run.x; i < run.y; ++i) {
    if (pixel_match[i] != kPixelNewSurfel) continue;
    if (index < params.capacity) surfels[index] = newSurfel(i);
    ++index;
  }
}

void main() {
  if (push.pass == 0u) {
    scanRuns();
  } else {
    writeSurfels();
  }
}
