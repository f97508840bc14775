#pragma once
// Pixel types of the preprocessing images, chosen so that a CPU ImageView over a mapped GPU buffer
// sees exactly the std430 layout the shaders write (vec4 = 16 bytes, vec2 = 8 bytes, tightly packed).

#include <Eigen/Core>
#include <cstdint>

namespace vifusion::preprocess {

/// One RGB888 pixel, bytes in memory order R, G, B.
struct Rgb8 {
  std::uint8_t r = 0;
  std::uint8_t g = 0;
  std::uint8_t b = 0;
};
static_assert(sizeof(Rgb8) == 3 && alignof(Rgb8) == 1, "RGB888 images must be tightly packed");

/// Vertex-map pixel: (x, y, z, 1) [m] in the camera frame; Zero() = invalid.
using VertexPixel = Eigen::Vector4f;
/// Normal-map pixel: (nx, ny, nz, 1), unit length, facing the camera; Zero() = invalid.
using NormalPixel = Eigen::Vector4f;
/// Gradient pixel: (∂I/∂u, ∂I/∂v) [intensity / px].
using GradientPixel = Eigen::Vector2f;

static_assert(sizeof(VertexPixel) == 16, "must match a std430 vec4 array element");
static_assert(sizeof(GradientPixel) == 8, "must match a std430 vec2 array element");

}  // namespace vifusion::preprocess
