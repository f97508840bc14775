#version 450
// map_index: the index map of the active surfels, one 1-pixel "splat" per surfel (ElasticFusion's
// index_map shaders, FACTOR 1). A surfel takes part when it is active (frame − updated ≤ δ_t),
// has confidence > 0 and projects inside the image at camera depth 0 < z ≤ max_depth_m.
//
// Two dispatches with a barrier between them make the result independent of execution order:
//   pass 0: index_depth[pixel] = atomicMin(floatBitsToUint(z))   (positive floats order like uints)
//   pass 1: surfels whose z bits equal index_depth[pixel] do atomicMax(index_id[pixel], id + 1),
//           so among surfels at exactly the same depth the highest index wins; 0 stays "none".
// The host clears index_depth to 0xFFFFFFFF and index_id to 0 before pass 0.
//
// Bindings (set 0, std430):
//   0  surfels      readonly  Surfel[capacity]  current surfel array
//   1  state        readonly  MapState          surfel_count, active_begin
//   2  params       readonly  FusionParams
//   3  index_depth            uint[w·h]
//   4  index_id               uint[w·h]
// Push constants: uint pass (0 or 1).
// One invocation per surfel, grid-stride over [active_begin, surfel_count): the inactive prefix holds no
// active surfel (map_state.glsl).
// CPU reference: vifusion::map::indexMapCpu.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 256) in;
layout(local_size_x_id = 0) in;

#include "map/fusion_params.glsl"
#include "map/map_state.glsl"
#include "map/surfel.glsl"

layout(push_constant) uniform Push { uint pass; } push;

layout(std430, binding = 0) restrict readonly buffer Surfels { Surfel surfels[]; };
layout(std430, binding = 1) restrict readonly buffer State { MapState state; };
layout(std430, binding = 2) restrict readonly buffer Params { FusionParams params; };
layout(std430, binding = 3) restrict buffer IndexDepth { uint index_depth[]; };
layout(std430, binding = 4) restrict buffer IndexId { uint index_id[]; };

void splat(uint id) {
  const Surfel s = surfels[id];
  if (!(s.position_confidence.w > 0.0)) return;
  if (float(params.frame) - s.colour_times.z > float(params.time_window_frames)) return;
  const vec3 p_C = transformPoint(params.T_C_W_rows, s.position_confidence.xyz);
  if (!(p_C.z > 0.0) || p_C.z > params.max_depth_m) return;
  const ivec2 pixel = projectToPixel(params, p_C);
  if (pixel.x < 0 || pixel.x >= params.width || pixel.y < 0 || pixel.y >= params.height) return;
  const int i = pixel.y * params.width + pixel.x;
  const uint z_bits = floatBitsToUint(p_C.z);
  if (push.pass == 0u) {
    atomicMin(index_depth[i], z_bits);
  } else if (index_depth[i] == z_bits) {
    atomicMax(index_id[i], id + 1u);
  }
}

void main() {
  const uint count = state.surfel_count;
  const uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint id = state.active_begin + gl_GlobalInvocationID.x; id < count; id += stride) splat(id);
}
