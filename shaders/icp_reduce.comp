#version 450
// Point-to-plane ICP of the current frame against the model prediction, reduced straight into
// normal equations (layout: include/reduce/normal_equations.glsl).
//
// For current pixel u with vertex p (camera frame C) the point q = T_ref_cur·p is projected into the
// reference (model) view; the model vertex v and normal n there (reference camera frame) give
//   r = nᵀ(q − v),   J = ∂r/∂δ = [nᵀ, (q × n)ᵀ]   for T_ref_cur ← exp(δ)·T_ref_cur, δ = [ρ, φ].
// Gates: both vertices valid, ‖q − v‖ ≤ max_distance_m, ‖R·n_cur × n‖ ≤ max_normal_sin.
// Candidates (the health ratio's denominator): pixels whose vertex lands on a valid model pixel.
// Weight: 1/σ_z(p.z)² (Kinect-style axial depth noise) times a Huber weight on r/σ_z.
// Systematic-error bound (term 30): e = σ_b·|p.w² − v.w²|, w the depths the two points were observed from
// (model maps carry it, frames 1): IcpOptions::inverse_depth_bias_sigma_per_m says why.
//
// binding 0: current vertices  vec4[w·h]  (x, y, z, z_obs or 1) camera frame [m], vec4(0) invalid
// binding 1: current normals   vec4[w·h]
// binding 2: model vertices    vec4[w·h]  (x, y, z, z_obs) reference camera frame [m]
// binding 3: model normals     vec4[w·h]
// binding 4: params            IcpParams
// binding 5: partials          float[groups · NE_STRIDE]
// Specialization: 0 = workgroup size (≥ 31); 3 = contiguous runs (1) or grid stride (0).
// CPU reference: vifusion::tracking::icpNormalEquationsCpu.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x_id = 0) in;

#include "tracking/icp_params.glsl"

layout(std430, binding = 0) restrict readonly buffer CurrentVertices { vec4 cur_vertices[]; };
layout(std430, binding = 1) restrict readonly buffer CurrentNormals { vec4 cur_normals[]; };
layout(std430, binding = 2) restrict readonly buffer ModelVertices { vec4 model_vertices[]; };
layout(std430, binding = 3) restrict readonly buffer ModelNormals { vec4 model_normals[]; };
layout(std430, binding = 4) restrict readonly buffer Params { IcpParams params; };
layout(std430, binding = 5) restrict writeonly buffer Partials { float partials[]; };

#include "reduce/normal_equations.glsl"

void neAddItem(inout float acc[NE_TERMS], int i) {
  const vec4 p = cur_vertices[i];
  if (!(p.z > 0.0)) return;
  const vec3 q = vec3(dot(params.T_ref_cur_rows[0], vec4(p.xyz, 1.0)), dot(params.T_ref_cur_rows[1], vec4(p.xyz, 1.0)),
                      dot(params.T_ref_cur_rows[2], vec4(p.xyz, 1.0)));
  if (!(q.z > 0.0)) return;
  // floor(x + 0.5), not round(): GLSL leaves the direction of halves to the implementation.
  const int u = int(floor(params.fx * q.x / q.z + params.cx + 0.5));
  const int v = int(floor(params.fy * q.y / q.z + params.cy + 0.5));
  if (u < 0 || u >= params.width || v < 0 || v >= params.height) return;
  const int j = v * params.width + u;
  const vec4 model_v = model_vertices[j];
  const vec4 model_n = model_normals[j];
  const vec4 cur_n = cur_normals[i];
  if (!(model_v.z > 0.0) || model_n.w == 0.0 || cur_n.w == 0.0) return;
  // A candidate is a pixel that has something to associate with: the health ratio then measures
  // alignment, not how much of the view the map already covers.
  neCountCandidate(acc);
  const vec3 diff = q - model_v.xyz;
  if (dot(diff, diff) > params.max_distance_m * params.max_distance_m) return;
  const vec3 rotated_n = vec3(dot(params.T_ref_cur_rows[0].xyz, cur_n.xyz), dot(params.T_ref_cur_rows[1].xyz, cur_n.xyz),
                              dot(params.T_ref_cur_rows[2].xyz, cur_n.xyz));
  const vec3 normal_cross = cross(rotated_n, model_n.xyz);
  if (dot(normal_cross, normal_cross) > params.max_normal_sin * params.max_normal_sin) return;

  const vec3 n = model_n.xyz;
  const float r = dot(n, diff);
  const float dz = p.z - params.sigma_z_z0_m;
  const float sigma = params.sigma_z_a_m + params.sigma_z_b_per_m * dz * dz;
  const float normalised = abs(r) / sigma;
  const float huber = normalised <= params.huber_k ? 1.0 : params.huber_k / normalised;
  const vec3 qxn = cross(q, n);
  const float J[6] = float[6](n.x, n.y, n.z, qxn.x, qxn.y, qxn.z);
  const float bias_lever_m2 = abs(p.w * p.w - model_v.w * model_v.w);
  neAccumulateBounded(acc, J, r, huber / (sigma * sigma), params.inverse_depth_bias_sigma_per_m * bias_lever_m2);
}

void main() { neReduceItems(params.width * params.height); }
