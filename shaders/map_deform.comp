#version 450
// map_deform: applies a deformation graph (loop closure, DESIGN.md §4.5) to every live surfel of the current
// array, in place. Each surfel is bound to its nodes by its creation frame (colour_times.y) and position, then
//   p' = Σ_k w_k (A_k (p − g_k) + g_k + t_k),   n' = normalize(Σ_k w_k A_k⁻ᵀ n)
// (φ of vifusion/loop/deformation_function.hpp); confidence, radius, colour and times are kept.
// The binding mirrors vifusion::loop::bindToNodes step by step (vifusion/loop/node_binding.hpp):
//   1. binary search of the time-sorted nodes for the first node not older than the surfel;
//   2. a window of `candidates` consecutive nodes around it, shifted (never shrunk) into [0, node_count);
//   3. the kBoundNodes = 4 nearest of them by distance (ties to the lower index), and the 5th, whose
//      distance d_max sets the weights w_k = (1 − d_k/d_max)², normalised; equal weights when d_max = 0 or
//      every weight is 0; with fewer candidates than 5, d_max is the farthest kept one's distance.
// A surfel whose whole window lies among the held nodes [0, first_moving_node) — the identity: nodes older
// than the last accepted closure — is neither bound nor written (after a first closure that is most of the
// map). A node's A⁻ᵀ is precomputed on the host (DeformationNode::inverse_transpose_columns).
//
// Bindings (set 0, std430):
//   0  state     readonly  map state: surfel_count
//   1  surfels             current surfel array (include/map/surfel.glsl), deformed in place
//   2  nodes     readonly  DeformationNode[node_count], sorted by creation frame (vifusion/map/surfel_deformation.hpp)
//   3  params    readonly  DeformParams (host-written per closure: node_count ≥ 1, candidates ≥ 1,
//                          first_moving_node ≤ node_count)
// Grid-stride over the surfels.
// CPU reference: vifusion::map::deformSurfelsCpu.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 128) in;
layout(local_size_x_id = 0) in;

#include "map/surfel.glsl"

struct DeformationNode {
  vec4 position_time;               // xyz g [m] in W; w the creation frame as uint bits
  vec4 columns[3];                  // A's columns; w of column c: t[c] [m]
  vec4 inverse_transpose_columns[3];  // A⁻ᵀ's columns (w unused)
};


layout(set = 0, binding = 0, std430) restrict readonly buffer MapState {
  uint surfel_count;
  uint overflow_count;
  uint state_frame;
  uint active_begin;
} state;
layout(set = 0, binding = 1, std430) restrict buffer Surfels { Surfel surfels[]; };
layout(set = 0, binding = 2, std430) restrict readonly buffer Nodes { DeformationNode nodes[]; };
layout(set = 0, binding = 3, std430) restrict readonly buffer DeformParams {
  uint node_count;  // ≥ 1
  uint candidates;  // window size, ≥ 1
  uint first_moving_node;  // nodes [0, first_moving_node) are the identity (held by the closure's solve)
  uint params_pad1;
} params;

const int kBoundNodes = 4;

uint nodeTime(int i) { return floatBitsToUint(nodes[i].position_time.w); }

int candidateWindowStart(uint time) {
  const int n = int(params.node_count);
  int lo = 0;
  int hi = n;
  while (lo < hi) {
    const int mid = lo + (hi - lo) / 2;
    if (nodeTime(mid) < time) {
      lo = mid + 1;
    } else {
      hi = mid;
    }
  }
  const int count = min(int(params.candidates), n);
  int start = lo - count / 2;
  if (start > n - count) start = n - count;
  if (start < 0) start = 0;
  return start;
}

// One node's share of φ: w·(A(p − g) + g + t) and w·A⁻ᵀn; a node of −1 (an unused slot) adds nothing.
void addNode(int node, float w, vec3 p, vec3 n_W, inout vec3 position, inout vec3 normal) {
  if (node < 0) return;
  const DeformationNode d = nodes[node];
  const mat3 A = mat3(d.columns[0].xyz, d.columns[1].xyz, d.columns[2].xyz);
  const vec3 t = vec3(d.columns[0].w, d.columns[1].w, d.columns[2].w);
  const vec3 g = d.position_time.xyz;
  position += w * (A * (p - g) + g + t);
  const mat3 A_inverse_transpose =
      mat3(d.inverse_transpose_columns[0].xyz, d.inverse_transpose_columns[1].xyz, d.inverse_transpose_columns[2].xyz);
  normal += w * (A_inverse_transpose * n_W);
}

// The nearest kBoundNodes candidates live in best_d2/best_node (x nearest … w) and the next one in
// fifth_d2/fifth_node; every access uses a constant component (no loop over slots, no private array): lavapipe
// addresses a variably indexed private array lane by lane through memory (the earlier insertion sort over
// float[5]: tests/bench/README.md, "Moving the map"). A candidate enters only if strictly nearer
// than the fifth; it then moves ahead of every slot it is strictly nearer than, and every slot behind it moves
// back by one (`shifting`), which is the CPU reference's insertion sort with ties to the lower index.
#define VIFUSION_DEFORM_INSERT(slot)                                   \
  if (shifting || d2 < best_d2.slot) {                                 \
    const float held_d2 = best_d2.slot;                                \
    const int held_node = best_node.slot;                              \
    best_d2.slot = d2;                                                 \
    best_node.slot = node;                                             \
    d2 = held_d2;                                                      \
    node = held_node;                                                  \
    shifting = true;                                                   \
  }

void main() {
  const int n = int(params.node_count);
  const int count = min(int(params.candidates), n);
  const int kept = min(count, kBoundNodes);
  const float infinity = uintBitsToFloat(0x7f800000u);
  const uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint s = gl_GlobalInvocationID.x; s < state.surfel_count; s += stride) {
    Surfel surfel = surfels[s];
    const vec3 p = surfel.position_confidence.xyz;
    const uint time = uint(surfel.colour_times.y);
    const int start = candidateWindowStart(time);
    if (start + count <= int(params.first_moving_node)) continue;  // bound to held nodes only: stays bit for bit

    vec4 best_d2 = vec4(infinity);
    ivec4 best_node = ivec4(-1);
    float fifth_d2 = infinity;
    int fifth_node = -1;
    for (int c = start; c < start + count; ++c) {
      const vec3 offset = nodes[c].position_time.xyz - p;
      float d2 = dot(offset, offset);
      if (!(d2 < fifth_d2)) continue;
      int node = c;
      bool shifting = false;
      VIFUSION_DEFORM_INSERT(x)
      VIFUSION_DEFORM_INSERT(y)
      VIFUSION_DEFORM_INSERT(z)
      VIFUSION_DEFORM_INSERT(w)
      fifth_d2 = d2;  // the candidate itself, or the slot it pushed out of the first four
      fifth_node = node;
    }
    const float last_kept_d2 = kept == 1 ? best_d2.x : kept == 2 ? best_d2.y : kept == 3 ? best_d2.z : best_d2.w;
    const float d_max = sqrt(count > kBoundNodes ? fifth_d2 : last_kept_d2);
    vec4 weight = vec4(0.0);
    if (d_max > 0.0) {
      weight = vec4(1.0) - sqrt(best_d2) / d_max;
      weight *= weight;
    }
    const bvec4 in_use = greaterThan(ivec4(kept), ivec4(0, 1, 2, 3));
    weight = mix(vec4(0.0), weight, in_use);  // a select: an unused slot's ∞ distance must not make 0·∞
    const float sum = weight.x + weight.y + weight.z + weight.w;
    weight = sum > 0.0 ? weight / sum : mix(vec4(0.0), vec4(1.0 / float(kept)), in_use);

    vec3 position = vec3(0.0);
    vec3 normal = vec3(0.0);
    const vec3 n_W = surfel.normal_radius.xyz;
    addNode(best_node.x, weight.x, p, n_W, position, normal);
    addNode(best_node.y, weight.y, p, n_W, position, normal);
    addNode(best_node.z, weight.z, p, n_W, position, normal);
    addNode(best_node.w, weight.w, p, n_W, position, normal);
    const float normal_length = length(normal);
    surfel.position_confidence.xyz = position;
    surfel.normal_radius.xyz = normal_length > 0.0 ? normal / normal_length : n_W;
    surfels[s] = surfel;
  }
}
