#version 450
// vertex_map: metric depth → camera-frame vertices by pinhole back-projection,
// x = (u − cx)/fx·z, y = (v − cy)/fy·z. fy keeps its sign (ICL-NUIM renders with fy < 0), which
// keeps back-projection consistent with projection. Pixel centres are at integer (u, v).
//
// Bindings (set 0, std430 storage buffers, images row-major and tightly packed, width × height):
//   0  depth_m   readonly   float[]  metric depth [m], 0 = invalid
//   1  vertices  writeonly  vec4[]   (x, y, z, 1) [m] in the camera frame, vec4(0) = invalid
// Push constants: VertexMapParams (vifusion/preprocess/kernel_params.hpp).
// CPU reference: vertexMapCpu. One invocation per output pixel.
#extension GL_GOOGLE_include_directive : require
#include "preprocess/common.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(local_size_x_id = 0, local_size_y_id = 1) in;

layout(push_constant) uniform Params {
  int width;   // [px]
  int height;  // [px]
  float fx;    // focal length along u [px]
  float fy;    // focal length along v [px], may be negative
  float cx;    // principal point u [px]
  float cy;    // principal point v [px]
} params;

layout(set = 0, binding = 0, std430) restrict readonly buffer Depth { float depth_m[]; };
layout(set = 0, binding = 1, std430) restrict writeonly buffer Vertices { vec4 vertices[]; };

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= params.width || pixel.y >= params.height) return;

  const int i = pixelIndex(pixel, params.width);
  const float z_m = depth_m[i];
  if (!isValidDepth(z_m)) {
    vertices[i] = vec4(0.0);
    return;
  }
  const float x_m = (float(pixel.x) - params.cx) / params.fx * z_m;
  const float y_m = (float(pixel.y) - params.cy) / params.fy * z_m;
  vertices[i] = vec4(x_m, y_m, z_m, 1.0);
}
