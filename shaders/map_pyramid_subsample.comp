#version 450
// map_pyramid_subsample: model maps of pyramid level l from level 0 by point sampling,
// dst(x, y) = src(2^l·x, 2^l·y). This matches PinholeCamera::atLevel (level-l pixel j sits on
// level-0 pixel 2^l·j, f_l = f_0/2^l, c_l = c_0/2^l), so each level is an exact camera-frame
// rendering at its own intrinsics. Not smoothed: averaging vertices across a depth edge would
// invent surface that no surfel has.
//
// Bindings (set 0, std430): 0 src vertices, 1 src normals, 2 src intensity (level 0, readonly),
//   3 dst vertices, 4 dst normals, 5 dst intensity (level l, writeonly).
// Push constants: src width, dst size, step 2^l [px]. CPU reference: subsampleModelCpu.
layout(local_size_x = 16, local_size_y = 16) in;
layout(local_size_x_id = 0, local_size_y_id = 1) in;

layout(push_constant) uniform Push {
  int src_width;   // [px]
  int dst_width;   // [px]
  int dst_height;  // [px]
  int step;        // 2^level
} push;

layout(set = 0, binding = 0, std430) restrict readonly buffer SrcVertices { vec4 src_vertices[]; };
layout(set = 0, binding = 1, std430) restrict readonly buffer SrcNormals { vec4 src_normals[]; };
layout(set = 0, binding = 2, std430) restrict readonly buffer SrcIntensity { float src_intensity[]; };
layout(set = 0, binding = 3, std430) restrict writeonly buffer DstVertices { vec4 dst_vertices[]; };
layout(set = 0, binding = 4, std430) restrict writeonly buffer DstNormals { vec4 dst_normals[]; };
layout(set = 0, binding = 5, std430) restrict writeonly buffer DstIntensity { float dst_intensity[]; };

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= push.dst_width || pixel.y >= push.dst_height) return;
  const int dst = pixel.y * push.dst_width + pixel.x;
  const int src = pixel.y * push.step * push.src_width + pixel.x * push.step;
  dst_vertices[dst] = src_vertices[src];
  dst_normals[dst] = src_normals[src];
  dst_intensity[dst] = src_intensity[src];
}
