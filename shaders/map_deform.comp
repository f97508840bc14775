#version 450
// map_deform: applies a deformation graph (loop closure, DESIGN.md §4.5) to every live surfel of the current
// array, in place. Each surfel is bound to its nodes by its creation frame (colour_times.y) and position, then
//   p' = Σ_k w_k (A_k (p − g_k) + g_k + t_k),   n' = normalize(Σ_k w_k A_k⁻ᵀ n)
// (φ of vifusion/loop/deformation_function.hpp); confidence, radius, colour and times are kept.
// The binding mirrors vifusion::loop::bindToNodes line by line (vifusion/loop/node_binding.hpp):
//   1. binary search of the time-sorted nodes for the first node not older than the surfel;
//   2. a window of `candidates` consecutive nodes around it, shifted (never shrunk) into [0, node_count);
//   3. the kBoundNodes = 4 nearest of them by distance (ties to the lower index), and the 5th, whose
//      distance d_max sets the weights w_k = (1 − d_k/d_max)², normalised; equal weights when d_max = 0 or
//      every weight is 0; with fewer candidates than 5, d_max is the farthest kept one's distance.
// A node's A⁻ᵀ is precomputed on the host (DeformationNode::inverse_transpose_columns).
//
// Bindings (set 0, std430):
//   0  state     readonly  map state: surfel_count
//   1  surfels             current surfel array (include/map/surfel.glsl), deformed in place
//   2  nodes     readonly  DeformationNode[node_count], sorted by creation frame (vifusion/map/surfel_deformation.hpp)
//   3  params    readonly  DeformParams (host-written per closure: node_count ≥ 1, candidates ≥ 1)
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
  uint state_pad;
} state;
layout(set = 0, binding = 1, std430) restrict buffer Surfels { Surfel surfels[]; };
layout(set = 0, binding = 2, std430) restrict readonly buffer Nodes { DeformationNode nodes[]; };
layout(set = 0, binding = 3, std430) restrict readonly buffer DeformParams {
  uint node_count;  // ≥ 1
  uint candidates;  // window size, ≥ 1
  uint params_pad0;
  uint params_pad1;
} params;

const int kBoundNodes = 4;
const int kKept = kBoundNodes + 1;

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

void main() {
  const int n = int(params.node_count);
  const int count = min(int(params.candidates), n);
  const uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint s = gl_GlobalInvocationID.x; s < state.surfel_count; s += stride) {
    Surfel surfel = surfels[s];
    const vec3 p = surfel.position_confidence.xyz;
    const uint time = uint(surfel.colour_times.y);
    const int start = candidateWindowStart(time);

    float best_d2[kKept];
    int best_node[kKept];
    for (int i = 0; i < kKept; ++i) {
      best_d2[i] = uintBitsToFloat(0x7f800000u);  // +inf
      best_node[i] = -1;
    }
    for (int c = start; c < start + count; ++c) {
      const vec3 d = nodes[c].position_time.xyz - p;
      const float d2 = dot(d, d);
      if (!(d2 < best_d2[kKept - 1])) continue;
      int j = kKept - 1;
      while (j > 0 && d2 < best_d2[j - 1]) {
        best_d2[j] = best_d2[j - 1];
        best_node[j] = best_node[j - 1];
        --j;
      }
      best_d2[j] = d2;
      best_node[j] = c;
    }
    const int kept = min(count, kBoundNodes);
    const float d_max = sqrt(count > kBoundNodes ? best_d2[kBoundNodes] : best_d2[kept - 1]);
    float weight[kBoundNodes];
    float sum = 0.0;
    for (int k = 0; k < kept; ++k) {
      float w = 0.0;
      if (d_max > 0.0) {
        const float u = 1.0 - sqrt(best_d2[k]) / d_max;
        w = u * u;
      }
      weight[k] = w;
      sum += w;
    }

    vec3 position = vec3(0.0);
    vec3 normal = vec3(0.0);
    const vec3 n_W = surfel.normal_radius.xyz;
    for (int k = 0; k < kept; ++k) {
      const float w = sum > 0.0 ? weight[k] / sum : 1.0 / float(kept);
      const DeformationNode node = nodes[best_node[k]];
      const mat3 A = mat3(node.columns[0].xyz, node.columns[1].xyz, node.columns[2].xyz);
      const vec3 t = vec3(node.columns[0].w, node.columns[1].w, node.columns[2].w);
      const vec3 g = node.position_time.xyz;
      position += w * (A * (p - g) + g + t);
      const mat3 A_inverse_transpose = mat3(node.inverse_transpose_columns[0].xyz,
                                            node.inverse_transpose_columns[1].xyz,
                                            node.inverse_transpose_columns[2].xyz);
      normal += w * (A_inverse_transpose * n_W);
    }
    const float normal_length = length(normal);
    surfel.position_confidence.xyz = position;
    surfel.normal_radius.xyz = normal_length > 0.0 ? normal / normal_length : n_W;
    surfels[s] = surfel;
  }
}
