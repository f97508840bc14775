#version 450
// Test kernel: out[i] = in[i] · push.scale + spec constant 3 (offset); exercises storage buffers,
// push constants and specialization constants.
// binding 0: in float[count]; binding 1: out float[count]
layout(local_size_x_id = 0) in;
layout(constant_id = 3) const float kOffset = 0.0;
layout(std430, binding = 0) readonly buffer In { float values_in[]; };
layout(std430, binding = 1) writeonly buffer Out { float values_out[]; };
layout(push_constant) uniform Params { uint count; float scale; } params;

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i >= params.count) return;
  values_out[i] = values_in[i] * params.scale + kOffset;
}
