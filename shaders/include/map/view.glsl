// The view a map kernel renders into or tests against: world → camera pose and level-0 intrinsics,
// plus the current frame number. Mirrored by vifusion::map::MapView (prediction_cpu.hpp).
//
// Every geometric helper here is written term by term with `precise` (no dot(), no fused
// multiply-add, divisions as a·(1/b)) so that the CPU references in pipeline/map/src/*_cpu.cpp
// reproduce the same floats bit for bit: splat winners and cleanup decisions are then identical on
// both sides, not merely close.
#ifndef VIFUSION_MAP_VIEW_GLSL
#define VIFUSION_MAP_VIEW_GLSL

struct MapView {
  vec4 T_C_W_rows[3];     // rows of the 3×4 transform world → camera [m]
  float fx, fy, cx, cy;   // level-0 intrinsics [px]; fy may be negative (ICL-NUIM)
  float inv_fx, inv_fy;   // 1/fx, 1/fy [1/px], computed once on the host
  int width, height;      // level-0 image size [px]
  uint frame;             // current frame number (the one whose data was fused last)
  uint pad0, pad1, pad2;
};

// p_C = R_C_W·p_W + t_C_W [m].
vec3 transformPoint(MapView view, vec3 p_W) {
  precise vec3 p_C;
  for (int r = 0; r < 3; ++r) {
    const vec4 row = view.T_C_W_rows[r];
    p_C[r] = ((row.x * p_W.x + row.y * p_W.y) + row.z * p_W.z) + row.w;
  }
  return p_C;
}

// n_C = R_C_W·n_W.
vec3 rotateVector(MapView view, vec3 n_W) {
  precise vec3 n_C;
  for (int r = 0; r < 3; ++r) {
    const vec4 row = view.T_C_W_rows[r];
    n_C[r] = (row.x * n_W.x + row.y * n_W.y) + row.z * n_W.z;
  }
  return n_C;
}

// Pixel coordinates of p_C (z > 0) [px]; pixel centres are integers.
vec2 projectPoint(MapView view, vec3 p_C) {
  precise float inv_z = 1.0 / p_C.z;
  precise vec2 uv = vec2(view.fx * (p_C.x * inv_z) + view.cx, view.fy * (p_C.y * inv_z) + view.cy);
  return uv;
}

// Frames since `frame_f` (a frame number stored as float in a surfel); 0 for future frames.
uint framesSince(MapView view, float frame_f) {
  const uint frame = uint(frame_f);
  return view.frame >= frame ? view.frame - frame : 0u;
}

#endif
