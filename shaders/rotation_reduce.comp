#version 450
// Rotation-only pre-alignment of the current frame against the previous frame (ElasticFusion's SO(3)
// step, algorithms.md §1.6), reduced straight into normal equations (include/reduce/normal_equations.glsl).
// A pure rotation maps pixels by the homography K·R_prev_cur·K⁻¹ whatever their depth, so the alignment
// needs no depth and no map: it sees the whole image even when the view has left the map, and it has only
// three unknowns, so it converges from far larger rotations than the six-parameter solve. The camera's
// translation between frames shows as parallax it cannot explain; at the coarsest level that is small.
//   ray x = K⁻¹·(u, v, 1),  q = R_prev_cur·x,
//   r = I_prev(π(q)) − I_cur(u),
//   J = ∇I_prev(π(q))·∂π/∂q·(−[q]×) = (q × g)ᵀ,  g = (∂π/∂q)ᵀ∇I_prev,
// for R_prev_cur ← exp(φ)·R_prev_cur. J is written into the rotation half of a 6-parameter row (the
// translation half is zero) so the reduction is the dense terms' own; the host solves the 3×3 block.
// I_prev and ∇I_prev are sampled bilinearly.
// Gates: the current pixel at least border_px inside the image, π(q) inside with its 2×2 neighbourhood,
// ‖∇I_prev‖ ≥ min_gradient. Every pixel has an intensity, so every such pixel is a candidate.
// Weight: 1/σ² times a Huber weight on r/σ, σ² = 2σ_I² (the noise of both images).
//
// binding 0: current intensity    float[w·h]  0..255
// binding 1: previous intensity   float[w·h]
// binding 2: previous gradients   vec2[w·h]   (∂I/∂u, ∂I/∂v)
// binding 3: params               RotationParams
// binding 4: partials             float[groups · NE_STRIDE]
// Specialization: 0 = workgroup size (≥ 31); 3 = contiguous runs (1) or grid stride (0).
// CPU reference: vifusion::tracking::rotationNormalEquationsCpu.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x_id = 0) in;

#include "tracking/rotation_params.glsl"

layout(std430, binding = 0) restrict readonly buffer CurrentIntensity { float cur_intensity[]; };
layout(std430, binding = 1) restrict readonly buffer PreviousIntensity { float prev_intensity[]; };
layout(std430, binding = 2) restrict readonly buffer PreviousGradients { vec2 prev_gradients[]; };
layout(std430, binding = 3) restrict readonly buffer Params { RotationParams params; };
layout(std430, binding = 4) restrict writeonly buffer Partials { float partials[]; };

#include "reduce/normal_equations.glsl"

void neAddItem(inout float acc[NE_TERMS], int i) {
  const int u = i % params.width;
  const int v = i / params.width;
  if (u < params.border_px || v < params.border_px || u >= params.width - params.border_px ||
      v >= params.height - params.border_px) {
    return;
  }
  neCountCandidate(acc);
  const vec3 ray = vec3((float(u) - params.cx) / params.fx, (float(v) - params.cy) / params.fy, 1.0);
  const vec3 q = vec3(dot(params.R_prev_cur_rows[0].xyz, ray), dot(params.R_prev_cur_rows[1].xyz, ray),
                      dot(params.R_prev_cur_rows[2].xyz, ray));
  if (!(q.z > 0.0)) return;
  const float inv_z = 1.0 / q.z;
  const float x = params.fx * q.x * inv_z + params.cx;
  const float y = params.fy * q.y * inv_z + params.cy;
  if (!(x >= 0.0 && y >= 0.0 && x < float(params.width - 1) && y < float(params.height - 1))) return;
  const int x0 = int(x);
  const int y0 = int(y);
  const float ax = x - float(x0);
  const float ay = y - float(y0);
  const int j = y0 * params.width + x0;
  const float w00 = (1.0 - ax) * (1.0 - ay), w10 = ax * (1.0 - ay), w01 = (1.0 - ax) * ay, w11 = ax * ay;
  const float intensity = w00 * prev_intensity[j] + w10 * prev_intensity[j + 1] +
                          w01 * prev_intensity[j + params.width] + w11 * prev_intensity[j + params.width + 1];
  const vec2 gradient = w00 * prev_gradients[j] + w10 * prev_gradients[j + 1] + w01 * prev_gradients[j + params.width] +
                        w11 * prev_gradients[j + params.width + 1];
  if (dot(gradient, gradient) < params.min_gradient * params.min_gradient) return;

  const float r = intensity - cur_intensity[i];
  const vec3 g = vec3(gradient.x * params.fx * inv_z, gradient.y * params.fy * inv_z,
                      -(gradient.x * params.fx * q.x + gradient.y * params.fy * q.y) * inv_z * inv_z);
  const vec3 qxg = cross(q, g);
  const float variance = 2.0 * params.sigma_intensity * params.sigma_intensity;
  const float normalised = abs(r) / sqrt(variance);
  const float huber = normalised <= params.huber_k ? 1.0 : params.huber_k / normalised;
  const float J[6] = float[6](0.0, 0.0, 0.0, qxg.x, qxg.y, qxg.z);
  neAccumulate(acc, J, r, huber / variance);
}

void main() { neReduceItems(params.width * params.height); }
