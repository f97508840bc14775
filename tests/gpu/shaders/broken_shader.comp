#version 450
// Deliberately broken (undeclared identifier on line 6): the build must stop with glslc's
// "file:line: error" message, which tests/gpu/CMakeLists.txt checks.
layout(local_size_x = 1) in;
void main() {
  undeclared_value = 1.0;
}
