#pragma once
// Pixel types of the preprocessing images, chosen so that a CPU ImageView over a mapped GPU buffer
// sees exactly the std430 layout the shaders write (vec4 = 16 bytes, vec2 = 8 bytes, tightly packed).

#include <Eigen/Core>
#include <cstdint>

#include "vifusion/core/image.hpp"

namespace vifusion::preprocess {

/// One RGB888 pixel (defined in core, where every sensor source uses it).
using Rgb8 = vifusion::Rgb8;

/// Vertex-map pixel: (x, y, z, 1) [m] in the camera frame; Zero() = invalid.
using VertexPixel = Eigen::Vector4f;
/// Normal-map pixel: (nx, ny, nz, 1), unit length, facing the camera; Zero() = invalid.
using NormalPixel = Eigen::Vector4f;
/// Gradient pixel: (∂I/∂u, ∂I/∂v) [intensity / px].
using GradientPixel = Eigen::Vector2f;

static_assert(sizeof(VertexPixel) == 16, "must match a std430 vec4 array element");
static_assert(sizeof(GradientPixel) == 8, "must match a std430 vec2 array element");

}  // namespace vifusion::preprocess
