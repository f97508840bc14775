#version 450
// map_sample: what loop closure reads out of the surfel map (pipeline/map map_sampling.hpp). Compiled twice:
//
//   VIFUSION_SAMPLE_GATHER=0 (map_sample_nodes): deformation-graph node samples. From the live surfels
//     [0, surfel_count) of the current array, every stride-th one, stride = max(1, ⌈surfel_count / max_nodes⌉),
//     computed here from the count the map state holds, so the host does not read the count first:
//       sample j = (p_W of surfel j·stride [m], its creation frame uint(colour_times.y)),  j < n,
//       n = ⌈surfel_count / stride⌉ ≤ max_nodes,
//     and the header (n, stride, surfel_count). The array is not in creation order (the inactive prefix,
//     then the active range: map_state.glsl); the graph sorts the samples by creation frame.
//   VIFUSION_SAMPLE_GATHER=1 (map_gather_points): loop-closure constraint points. For each of point_count
//     level-0 pixels written by the host, the surfel that won that pixel in one ModelPrediction (its splat id
//     image): the surfel's centre in W [m] (not the ray–disk intersection the vertex map holds), its normal in
//     W, creation and last-update frames, its index; valid = 0 and the rest zero (index kNoSurfel) where no
//     surfel won, the pixel lies outside the image, or the id is not below surfel_count. The ids index the
//     array the prediction rendered: bind that parity (map_sampling.hpp says which it is in Slam's frame).
// Both are copies: fields are moved, never recomputed, so the CPU references agree bit for bit.
//
// Bindings (set 0, std430):
//   nodes:   0 state readonly (surfel_count) | 1 surfels readonly | 2 samples writeonly NodeSample[max_nodes]
//            | 3 header writeonly NodeSampleHeader
//   gather:  0 state readonly (surfel_count) | 1 surfels readonly | 2 points writeonly GatheredPoint[max_points]
//            | 3 params readonly GatherParams (host-written) | 4 pixels readonly ivec2[max_points] (host-written)
//            | 5 ids readonly uint per level-0 pixel of the prediction, kNoSurfel = none
// Specialization constant 3 (nodes): max_nodes ≥ 1. Grid-stride over the samples / points.
// CPU references: vifusion::map::sampleNodesCpu and gatherPointsCpu.
#extension GL_GOOGLE_include_directive : require
#include "map/surfel.glsl"

layout(local_size_x = 64) in;
layout(local_size_x_id = 0) in;

layout(set = 0, binding = 0, std430) restrict readonly buffer MapState {
  uint surfel_count;
  uint overflow_count;
  uint state_frame;
  uint active_begin;
} state;
layout(set = 0, binding = 1, std430) restrict readonly buffer Surfels { Surfel surfels[]; };

#if VIFUSION_SAMPLE_GATHER == 0

layout(constant_id = 3) const uint kMaxNodes = 1024u;

struct NodeSample {
  vec3 p_W;           // surfel position in W [m]
  uint created_frame; // uint(colour_times.y)
};
layout(set = 0, binding = 2, std430) restrict writeonly buffer Samples { NodeSample samples[]; };
layout(set = 0, binding = 3, std430) restrict writeonly buffer Header {
  uint sample_count;  // samples written, ≤ max_nodes
  uint stride;        // surfels between samples, ≥ 1
  uint sampled_surfel_count;  // the surfel_count they were taken from
  uint header_pad;
} header;

void main() {
  const uint count = state.surfel_count;
  // ⌈count / max_nodes⌉ without forming count + max_nodes − 1, which could wrap.
  const uint stride = max(1u, count / kMaxNodes + (count % kMaxNodes != 0u ? 1u : 0u));
  const uint n = count == 0u ? 0u : (count - 1u) / stride + 1u;
  if (gl_GlobalInvocationID.x == 0u) {
    header.sample_count = n;
    header.stride = stride;
    header.sampled_surfel_count = count;
    header.header_pad = 0u;
  }
  const uint grid = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint j = gl_GlobalInvocationID.x; j < n; j += grid) {
    const Surfel s = surfels[j * stride];  // j < n, so j·stride < count: no wrap
    samples[j] = NodeSample(s.position_confidence.xyz, uint(s.colour_times.y));
  }
}

#else

const uint kNoSurfel = 0xffffffffu;  // as prediction.glsl

struct GatheredPoint {
  vec3 p_W;            // surfel centre in W [m]
  uint created_frame;  // uint(colour_times.y)
  vec3 n_W;            // surfel normal in W, as stored
  uint updated_frame;  // uint(colour_times.z)
  uint surfel;         // index in the rendered array, kNoSurfel when invalid
  uint valid;          // 1: a surfel won the pixel; 0: none (every other field zero)
  uint pad0, pad1;
};
layout(set = 0, binding = 2, std430) restrict writeonly buffer Points { GatheredPoint points[]; };
layout(set = 0, binding = 3, std430) restrict readonly buffer GatherParams {
  uint point_count;  // pixels written by the host, ≤ max_points
  int width;         // level-0 image size of the prediction [px]
  int height;
  uint params_pad;
} params;
layout(set = 0, binding = 4, std430) restrict readonly buffer Pixels { ivec2 pixels[]; };
layout(set = 0, binding = 5, std430) restrict readonly buffer Ids { uint ids[]; };

void main() {
  const uint count = state.surfel_count;
  const uint grid = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint j = gl_GlobalInvocationID.x; j < params.point_count; j += grid) {
    const ivec2 pixel = pixels[j];
    const bool inside = pixel.x >= 0 && pixel.y >= 0 && pixel.x < params.width && pixel.y < params.height;
    const uint id = inside ? ids[uint(pixel.y * params.width + pixel.x)] : kNoSurfel;
    if (id == kNoSurfel || id >= count) {
      points[j] = GatheredPoint(vec3(0.0), 0u, vec3(0.0), 0u, kNoSurfel, 0u, 0u, 0u);
      continue;
    }
    const Surfel s = surfels[id];
    points[j] = GatheredPoint(s.position_confidence.xyz, uint(s.colour_times.y), s.normal_radius.xyz,
                              uint(s.colour_times.z), id, 1u, 0u, 0u);
  }
}

#endif
