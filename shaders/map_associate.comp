#version 450
// map_associate: data association of the current frame's pixels with the index map (ElasticFusion's
// data.* shaders, on the pixel's own 3 × 3 window of the index map instead of 4 × 4 half-pixel taps).
//
// Pixel i with camera-frame vertex p and normal n (level-0 maps; needs both valid and z ≤ max depth)
// looks at the surfels of the 3 × 3 index-map window around it. A surfel with camera-frame position
// x and normal m is a candidate when
//   |x.z − p.z| · ‖p‖/p.z < max_depth_diff_m        (depth difference along the pixel ray)
//   m·n > cos(max angle)  or  |m.z| < grazing_normal_z
// and the winner has the smallest distance to the pixel ray, ties to the lower surfel index.
// Both gates and the distance are compared multiplied out (no division, no square root):
//   (x.z − p.z)²·‖p‖² < τ²·p.z²   and   ‖x × p‖² (= distance² · ‖p‖²).
// Output pixel_match[i]: surfel index + 1, kPixelNewSurfel (no candidate), kPixelNoMeasurement.
// A matched pixel claims its surfel with atomicMin(surfel_claim[id], i): the lowest pixel index
// wins, whatever the execution order, and only that pixel updates the surfel (map_fuse).
//
// One invocation per run: a segment of up to kRunPixels consecutive pixels of one row (the runs of
// map_insert, in pixel order). The invocation walks it with a sliding 3 × 3 window: moving one pixel
// right keeps six of the nine candidates (index entry, surfel, its camera-frame position and
// normal) and reads one new column, so a pixel costs 3 index reads and 3 surfel reads instead of 9
// and 9 (lavapipe reads storage buffers lane by lane, so the reads were the cost). Candidates are
// still compared in the same order, so the winners are the same. Each run also counts its
// kPixelNewSurfel pixels into run_counts[run], which map_insert's scan turns into offsets (it has
// no counting pass of its own).
//
// Bindings (set 0, std430):
//   0  vertices      readonly  vec4[w·h]  (x, y, z, 1) camera frame [m], vec4(0) invalid
//   1  normals       readonly  vec4[w·h]  (n, 1) camera frame, vec4(0) invalid
//   2  surfels       readonly  Surfel[capacity]  current surfel array
//   3  index_id      readonly  uint[w·h]  surfel index + 1, 0 = none
//   4  params        readonly  FusionParams
//   5  pixel_match   writeonly uint[w·h]
//   6  surfel_claim            uint[capacity], kUnclaimed before this kernel
//   7  run_counts    writeonly uint[runs]  kPixelNewSurfel pixels per run (fusion_params.glsl: pixelRun)
// One invocation per run; specialization 3 = kRunPixels. CPU reference: vifusion::map::associateCpu.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 256) in;
layout(local_size_x_id = 0) in;
layout(constant_id = 3) const uint kRunPixels = 32;

#include "map/fusion_params.glsl"
#include "map/surfel.glsl"

layout(std430, binding = 0) restrict readonly buffer Vertices { vec4 vertices[]; };
layout(std430, binding = 1) restrict readonly buffer Normals { vec4 normals[]; };
layout(std430, binding = 2) restrict readonly buffer Surfels { Surfel surfels[]; };
layout(std430, binding = 3) restrict readonly buffer IndexId { uint index_id[]; };
layout(std430, binding = 4) restrict readonly buffer Params { FusionParams params; };
layout(std430, binding = 5) restrict writeonly buffer PixelMatch { uint pixel_match[]; };
layout(std430, binding = 6) restrict buffer SurfelClaim { uint surfel_claim[]; };
layout(std430, binding = 7) restrict writeonly buffer RunCounts { uint run_counts[]; };

// The index-map entry at one window position, with its surfel in the camera frame.
struct Candidate {
  uint id;    // surfel index + 1, 0 = none (or outside the image)
  vec3 x_C;   // position [m]
  vec3 m_C;   // normal
};

Candidate loadCandidate(int x, int y) {
  Candidate c = Candidate(0u, vec3(0.0), vec3(0.0));
  if (x < 0 || x >= params.width || y < 0 || y >= params.height) return c;
  c.id = index_id[y * params.width + x];
  if (c.id == 0u) return c;
  const Surfel s = surfels[c.id - 1u];
  c.x_C = transformPoint(params.T_C_W_rows, s.position_confidence.xyz);
  c.m_C = rotateVector(params.T_C_W_rows, s.normal_radius.xyz);
  return c;
}

// The measurement of one pixel and the best candidate so far.
struct Match {
  vec3 p;            // vertex [m]
  vec3 n;            // normal
  float p_sq;        // ‖p‖²
  float depth_gate;  // τ²·p.z²
  uint best;         // surfel index + 1, 0 = none yet
  float best_distance;
};

// Straight-line on purpose: the gates and the comparison are computed for every candidate and
// combined as booleans, and the best candidate is updated by selects. Early returns and short-circuit
// operands became nested branches, which lavapipe executes as masked code for all lanes anyway,
// with a select per live value at every join (measured: the comparisons were 2/3 of the kernel).
void consider(inout Match m, Candidate c) {
  precise float dz = c.x_C.z - m.p.z;
  precise float depth_term = dz * dz * m.p_sq;
  precise float normal_cos = c.m_C.x * m.n.x + c.m_C.y * m.n.y + c.m_C.z * m.n.z;
  precise float cx = c.x_C.y * m.p.z - c.x_C.z * m.p.y;
  precise float cy = c.x_C.z * m.p.x - c.x_C.x * m.p.z;
  precise float cz = c.x_C.x * m.p.y - c.x_C.y * m.p.x;
  precise float distance = cx * cx + cy * cy + cz * cz;
  const bool present = c.id != 0u;
  const bool near = depth_term < m.depth_gate;
  const bool facing = normal_cos > params.min_normal_cos;
  const bool grazing = abs(c.m_C.z) < params.grazing_normal_z;
  const bool first = m.best == 0u;
  const bool closer = distance < m.best_distance;
  const bool tie = distance == m.best_distance;
  const bool lower = c.id < m.best;
  const bool accepted = present && near && (facing || grazing);
  const bool better = first || closer || (tie && lower);
  const bool take = accepted && better;
  m.best = take ? c.id : m.best;
  m.best_distance = take ? distance : m.best_distance;
}

// The candidates of index-map column x, rows v − 1, v, v + 1.
struct Column {
  Candidate above, centre, below;
};

Column loadColumn(int x, int v) { return Column(loadCandidate(x, v - 1), loadCandidate(x, v), loadCandidate(x, v + 1)); }

void main() {
  const uvec3 run = pixelRun(params, kRunPixels, gl_GlobalInvocationID.x);  // first, end pixel; row
  if (run.x >= run.y) return;
  const int v = int(run.z);
  const int first_u = int(run.x) - v * params.width;
  // The window of the pixel before: columns u − 1, u, u + 1. Every step reads one new column, so
  // every lane runs the same code (lavapipe executes both sides of a divergent branch).
  Column left;
  Column centre = loadColumn(first_u - 1, v);
  Column right = loadColumn(first_u, v);
  uint new_surfels = 0u;
  for (uint i = run.x; i < run.y; ++i) {
    const int u = first_u + int(i - run.x);
    left = centre;
    centre = right;
    right = loadColumn(u + 1, v);

    const vec4 p = vertices[i];
    const vec4 n = normals[i];
    if (!(p.z > 0.0) || p.z > params.max_depth_m || n.w == 0.0) {
      pixel_match[i] = kPixelNoMeasurement;
      continue;
    }
    Match m;
    m.p = p.xyz;
    m.n = n.xyz;
    precise float p_sq = p.x * p.x + p.y * p.y + p.z * p.z;
    precise float depth_gate = params.max_depth_diff_m * params.max_depth_diff_m * p.z * p.z;
    m.p_sq = p_sq;
    m.depth_gate = depth_gate;
    m.best = 0u;
    m.best_distance = 0.0;
    // Row by row, left to right, as the CPU reference.
    consider(m, left.above);
    consider(m, centre.above);
    consider(m, right.above);
    consider(m, left.centre);
    consider(m, centre.centre);
    consider(m, right.centre);
    consider(m, left.below);
    consider(m, centre.below);
    consider(m, right.below);
    if (m.best == 0u) {
      pixel_match[i] = kPixelNewSurfel;
      ++new_surfels;
      continue;
    }
    pixel_match[i] = m.best;
    atomicMin(surfel_claim[m.best - 1u], i);
  }
  run_counts[gl_GlobalInvocationID.x] = new_surfels;
}
