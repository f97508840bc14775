#version 450
// Photometric alignment of the current frame against the reference (model) intensity image,
// reduced straight into normal equations (include/reduce/normal_equations.glsl). As the paper:
//   r = I_ref(π(q)) − I_cur(u),  q = T_ref_cur·p(u)  (p from the current depth, camera frame)
//   J = ∇I_ref(π(q))·∂π/∂q·[I, −[q]×] = [gᵀ, (q × g)ᵀ],  g = (∂π/∂q)ᵀ∇I_ref,
// for T_ref_cur ← exp(δ)·T_ref_cur, δ = [ρ, φ]. I_ref and ∇I_ref are sampled bilinearly.
// Gates: current vertex valid, π(q) inside the image with its 2×2 neighbourhood, reference depth
// at π(q) valid and within max_depth_difference_m of q.z (occlusions), ‖∇I_ref‖ ≥ min_gradient,
// and reference depth valid on the whole support of the sample (support_radius_px). A reference pixel is
// model when its depth is valid and, unless use_reference_fill, the map predicted it (vertex w ≠ 0; the
// fill-in from the previous frame has w = 0, slam/reference_fill.hpp).
// Weight: 1/σ² times a Huber weight on r/σ, σ² = σ_I² + (σ_px·‖∇I_ref‖)² (intensity noise plus the
// positional uncertainty of the predicted reference image, PhotometricOptions).
//
// binding 0: current vertices     vec4[w·h]   camera frame [m]
// binding 1: current intensity    float[w·h]  0..255
// binding 2: reference intensity  float[w·h]
// binding 3: reference gradients  vec2[w·h]   (∂I/∂u, ∂I/∂v)
// binding 4: reference vertices   vec4[w·h]   reference camera frame [m]
// binding 5: params               PhotometricParams
// binding 6: partials             float[groups · NE_STRIDE]
// Specialization: 0 = workgroup size (≥ 31); 3 = contiguous runs (1) or grid stride (0).
// CPU reference: vifusion::tracking::photometricNormalEquationsCpu.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x_id = 0) in;

#include "tracking/photometric_params.glsl"

layout(std430, binding = 0) restrict readonly buffer CurrentVertices { vec4 cur_vertices[]; };
layout(std430, binding = 1) restrict readonly buffer CurrentIntensity { float cur_intensity[]; };
layout(std430, binding = 2) restrict readonly buffer ReferenceIntensity { float ref_intensity[]; };
layout(std430, binding = 3) restrict readonly buffer ReferenceGradients { vec2 ref_gradients[]; };
layout(std430, binding = 4) restrict readonly buffer ReferenceVertices { vec4 ref_vertices[]; };
layout(std430, binding = 5) restrict readonly buffer Params { PhotometricParams params; };
layout(std430, binding = 6) restrict writeonly buffer Partials { float partials[]; };

#include "reduce/normal_equations.glsl"

bool onModel(vec4 reference_vertex) {
  return reference_vertex.z > 0.0 && (params.use_reference_fill != 0 || reference_vertex.w != 0.0);
}

void neAddItem(inout float acc[NE_TERMS], int i) {
  const vec4 p = cur_vertices[i];
  if (!(p.z > 0.0)) return;
  neCountCandidate(acc);
  const vec4 p1 = vec4(p.xyz, 1.0);
  const vec3 q = vec3(dot(params.T_ref_cur_rows[0], p1), dot(params.T_ref_cur_rows[1], p1),
                      dot(params.T_ref_cur_rows[2], p1));
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
  // Occlusion gate on the nearest reference pixel's depth.
  const int nearest = j + (ay >= 0.5 ? params.width : 0) + (ax >= 0.5 ? 1 : 0);
  const vec4 v_ref = ref_vertices[nearest];
  if (!onModel(v_ref) || abs(q.z - v_ref.z) > params.max_depth_difference_m) return;

  const float w00 = (1.0 - ax) * (1.0 - ay), w10 = ax * (1.0 - ay), w01 = (1.0 - ax) * ay, w11 = ax * ay;
  const float intensity = w00 * ref_intensity[j] + w10 * ref_intensity[j + 1] + w01 * ref_intensity[j + params.width] +
                          w11 * ref_intensity[j + params.width + 1];
  const vec2 gradient = w00 * ref_gradients[j] + w10 * ref_gradients[j + 1] + w01 * ref_gradients[j + params.width] +
                        w11 * ref_gradients[j + params.width + 1];
  if (dot(gradient, gradient) < params.min_gradient * params.min_gradient) return;
  // Every reference pixel the interpolated intensity and gradient depend on must be a predicted one
  // (coordinates clamped like the gradient and pyramid kernels): next to a hole of the prediction,
  // whose intensity is 0, they would describe an edge that is not in the scene.
  for (int dy = 1 - params.support_radius_px; dy <= params.support_radius_px; ++dy) {
    const int row = clamp(y0 + dy, 0, params.height - 1) * params.width;
    for (int dx = 1 - params.support_radius_px; dx <= params.support_radius_px; ++dx) {
      if (!onModel(ref_vertices[row + clamp(x0 + dx, 0, params.width - 1)])) return;
    }
  }

  const float r = intensity - cur_intensity[i];
  const vec3 g = vec3(gradient.x * params.fx * inv_z, gradient.y * params.fy * inv_z,
                      -(gradient.x * params.fx * q.x + gradient.y * params.fy * q.y) * inv_z * inv_z);
  const vec3 qxg = cross(q, g);
  const float variance = params.sigma_intensity * params.sigma_intensity +
                         params.sigma_position_px * params.sigma_position_px * dot(gradient, gradient);
  const float normalised = abs(r) / sqrt(variance);
  const float huber = normalised <= params.huber_k ? 1.0 : params.huber_k / normalised;
  const float J[6] = float[6](g.x, g.y, g.z, qxg.x, qxg.y, qxg.z);
  neAccumulate(acc, J, r, huber / variance);
}

void main() { neReduceItems(params.width * params.height); }
