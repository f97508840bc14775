#version 450
// Generic normal-equation reduction: sums rows [J (6), r, w] into per-workgroup partials of
// Jᵀ W J, Jᵀ W r, Σ w r² and the inlier count (layout in include/reduce/normal_equations.glsl).
//
// binding 0: rows      vec4[2·row_count]: (J0, J1, J2, J3), (J4, J5, r, w); w = 0 skips a row
// binding 1: partials  float[groups · NE_STRIDE]
//
// Specialization: 0 = workgroup size (≥ 31); 3 = contiguous runs (1) or grid stride (0).

layout(local_size_x_id = 0) in;

layout(std430, binding = 0) readonly buffer Rows { vec4 rows[]; };
layout(std430, binding = 1) writeonly buffer Partials { float partials[]; };
layout(push_constant) uniform Params { uint row_count; } params;

#include "reduce/normal_equations.glsl"

void neAddItem(inout float acc[NE_TERMS], int row) {
  const vec4 a = rows[2 * row];
  const vec4 b = rows[2 * row + 1];
  const float J[6] = float[6](a.x, a.y, a.z, a.w, b.x, b.y);
  neCountCandidate(acc);
  neAccumulate(acc, J, b.z, b.w);
}

void main() { neReduceItems(int(params.row_count)); }
