#version 450
// reference_fill: fills the holes of the tracker's reference view (the map's prediction at this frame's
// pose) with this frame's own measurements for the photometric term, so the next frame is aligned to the
// map where the map has stable surfels and frame to frame elsewhere (after ElasticFusion's fill-in,
// algorithms.md §1.2 4a). Where the camera turns into a view faster than new surfels become stable (ten or
// more observations), the prediction covers little of it; this frame, at the pose the reference is
// rendered at, covers all of it. Both are in the same camera frame, so a hole is filled by a copy.
//
// Only the photometric term sees the fill, and only when asked: a filled vertex carries w = 0, which
// photometric_reduce.comp counts as model only with use_reference_fill (Slam's fallback for a frame the map
// alone does not track), and a filled normal w = 0, which the ICP reads as "no model" (icp_reduce.comp), so
// the ICP stays frame to model: point-to-plane between two raw depth images locks onto the disparity
// quantisation bands both share (tests/bench/README.md, "Reference fill-in").
//
//   pass 0 (level 0): counts[0] += pixels where this frame has a vertex, counts[1] += those of them the
//                     prediction covers (one atomic add per workgroup after a shared-memory sum): the
//                     coverage the host reports;
//   pass 1 (every level): a pixel whose reference vertex is invalid (z ≤ 0) and current vertex valid takes
//                     the current vertex and normal, both with w = 0 (kFilledVertexW), at level 0 also the
//                     intensity (the coarser reference intensities are built from level 0 afterwards).
//                     Pixels the prediction covers are left alone.
// The host clears counts before pass 0 and reads them after the submission.
//
// Bindings (set 0, std430, one level, row-major):
//   0  current vertices     readonly  vec4[w·h]  camera frame [m], vec4(0) invalid
//   1  current normals      readonly  vec4[w·h]
//   2  current intensity    readonly  float[w·h]  0..255
//   3  reference vertices             vec4[w·h]  same camera frame [m], vec4(0) = no model
//   4  reference normals              vec4[w·h]
//   5  reference intensity            float[w·h]
//   6  counts                         uint[2]  valid pixels, covered pixels (level 0)
// Push constants: ReferenceFillParams (vifusion/slam/reference_fill.hpp). One invocation per pixel.
// CPU reference: vifusion::slam::referenceCoverageCpu and referenceFillCpu.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 16, local_size_y = 16) in;
layout(local_size_x_id = 0, local_size_y_id = 1) in;

layout(push_constant) uniform Params {
  int width;            // level size [px]
  int height;
  uint fill_intensity;  // 1 at level 0
  uint pass;            // 0: count (level 0), 1: fill
} params;

layout(set = 0, binding = 0, std430) restrict readonly buffer CurrentVertices { vec4 cur_vertices[]; };
layout(set = 0, binding = 1, std430) restrict readonly buffer CurrentNormals { vec4 cur_normals[]; };
layout(set = 0, binding = 2, std430) restrict readonly buffer CurrentIntensity { float cur_intensity[]; };
layout(set = 0, binding = 3, std430) restrict buffer ReferenceVertices { vec4 ref_vertices[]; };
layout(set = 0, binding = 4, std430) restrict buffer ReferenceNormals { vec4 ref_normals[]; };
layout(set = 0, binding = 5, std430) restrict buffer ReferenceIntensity { float ref_intensity[]; };
layout(set = 0, binding = 6, std430) restrict buffer Counts { uint counts[2]; };

shared uint workgroup_valid;
shared uint workgroup_covered;

void count(bool inside, int i) {
  if (gl_LocalInvocationIndex == 0u) {
    workgroup_valid = 0u;
    workgroup_covered = 0u;
  }
  barrier();
  if (inside && cur_vertices[i].z > 0.0) {
    atomicAdd(workgroup_valid, 1u);
    if (ref_vertices[i].z > 0.0) atomicAdd(workgroup_covered, 1u);
  }
  barrier();
  if (gl_LocalInvocationIndex == 0u) {
    if (workgroup_valid > 0u) atomicAdd(counts[0], workgroup_valid);
    if (workgroup_covered > 0u) atomicAdd(counts[1], workgroup_covered);
  }
}

void fill(int i) {
  if (ref_vertices[i].z > 0.0) return;
  const vec4 p = cur_vertices[i];
  if (!(p.z > 0.0)) return;
  ref_vertices[i] = vec4(p.xyz, 0.0);
  ref_normals[i] = vec4(cur_normals[i].xyz, 0.0);
  if (params.fill_intensity != 0u) ref_intensity[i] = cur_intensity[i];
}

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  const bool inside = pixel.x < params.width && pixel.y < params.height;
  const int i = pixel.y * params.width + pixel.x;
  if (params.pass == 0u) {
    count(inside, i);  // every invocation reaches the barriers
  } else if (inside) {
    fill(i);
  }
}
