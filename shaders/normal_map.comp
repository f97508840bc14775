#version 450
// normal_map: camera-frame vertices → unit surface normals from central differences s = span_px
// pixels either side, n ∝ (v(x+s, y) − v(x−s, y)) × (v(x, y+s) − v(x, y−s)), oriented towards the
// camera (n·v < 0). The span is wider than one pixel because structured-light depth is quantised
// into plateaus several pixels wide: one-pixel differences there give the plateau's (fronto-parallel)
// normal, not the surface's. Invalid (vec4(0)) when the pixel or any of the four neighbours is
// invalid or outside the image (so an s-pixel border is always invalid), or when the cross product is
// degenerate:
// |a × b| < min_cross_norm_m2, where |a × b| is the area [m²] of the parallelogram spanned by the two
// differences (collinear or coincident vertices).
//
// Bindings (set 0, std430 storage buffers, images row-major and tightly packed, width × height):
//   0  vertices  readonly   vec4[]  (x, y, z, ·) [m] in the camera frame, invalid when z ≤ 0
//   1  normals   writeonly  vec4[]  (nx, ny, nz, 1), unit length, vec4(0) = invalid
// Push constants: NormalMapParams (vifusion/preprocess/kernel_params.hpp).
// CPU reference: normalMapCpu. One invocation per output pixel.
#extension GL_GOOGLE_include_directive : require
#include "preprocess/common.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(local_size_x_id = 0, local_size_y_id = 1) in;

layout(push_constant) uniform Params {
  int width;                // [px]
  int height;               // [px]
  float min_cross_norm_m2;  // smallest accepted |a × b| [m²]
  int span_px;              // s ≥ 1 [px]
} params;

layout(set = 0, binding = 0, std430) restrict readonly buffer Vertices { vec4 vertices[]; };
layout(set = 0, binding = 1, std430) restrict writeonly buffer Normals { vec4 normals[]; };

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= params.width || pixel.y >= params.height) return;

  const int i = pixelIndex(pixel, params.width);
  const int s = params.span_px;
  if (pixel.x < s || pixel.y < s || pixel.x + s >= params.width || pixel.y + s >= params.height) {
    normals[i] = vec4(0.0);
    return;
  }
  const vec4 v = vertices[i];
  const vec4 left = vertices[i - s];
  const vec4 right = vertices[i + s];
  const vec4 above = vertices[i - s * params.width];
  const vec4 below = vertices[i + s * params.width];
  if (!isValidVertex(v) || !isValidVertex(left) || !isValidVertex(right) || !isValidVertex(above) ||
      !isValidVertex(below)) {
    normals[i] = vec4(0.0);
    return;
  }

  // Cross product, squared norm and orientation test are spelled out (not cross()/dot()/normalize())
  // so that the operation order is the one the CPU reference uses.
  const vec3 a = right.xyz - left.xyz;
  const vec3 b = below.xyz - above.xyz;
  const vec3 c = vec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
  const float norm_sq = c.x * c.x + c.y * c.y + c.z * c.z;
  if (norm_sq < params.min_cross_norm_m2 * params.min_cross_norm_m2) {
    normals[i] = vec4(0.0);
    return;
  }
  vec3 n = c / sqrt(norm_sq);
  if (n.x * v.x + n.y * v.y + n.z * v.z > 0.0) n = -n;
  normals[i] = vec4(n, 1.0);
}
