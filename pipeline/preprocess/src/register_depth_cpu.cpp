// CPU reference of shaders/register_depth.comp (both passes). Compiled with -ffp-contract=off
// (pipeline/preprocess/CMakeLists.txt) so that no a·b + c becomes one FMA: the shader marks the same
// expressions `precise`, and every sum and product then rounds once, identically on both sides.

#include <cmath>
#include <cstdint>

#include "view_checks.hpp"
#include "vifusion/preprocess/cpu_reference.hpp"

namespace vifusion::preprocess {
namespace {

/// Largest raw depth an output pixel can hold [units] (uint16).
constexpr float kMaxRawDepth = 65535.0f;

/// The shader's nearestPixel: the colour pixel index k along one axis with homogeneous coordinate h
/// and depth h_z > 0, defined as the largest k with fl((k − ½)·h_z) ≤ h (round half up, decided by
/// correctly rounded products only); −1 outside 0..size−1. h / h_z only proposes k: a GPU may divide
/// 2.5 ulp off, and the two comparisons move the proposal by one where it fell on the wrong side.
int nearestPixel(float h, float h_z, int size) {
  const float q = h / h_z;
  // Integers are far from the rounding boundaries (half-integers), so a q on either side of −1 or
  // size gives a k outside the image on every device: the guard cannot make CPU and GPU differ.
  if (!(q > -1.0f && q < static_cast<float>(size))) return -1;
  int k = static_cast<int>(std::floor(q + 0.5f));
  const float lower = (static_cast<float>(k) - 0.5f) * h_z;
  const float upper = (static_cast<float>(k) + 0.5f) * h_z;
  if (h < lower) {
    k -= 1;
  } else if (h >= upper) {
    k += 1;
  }
  return k >= 0 && k < size ? k : -1;
}

}  // namespace

void registerDepthCpu(ImageView<const std::uint16_t> raw, const RegisterDepthParams& params,
                      ImageView<std::uint16_t> registered) {
  detail::requireSize(raw, params.depth_width, params.depth_height, "registerDepthCpu", "raw");
  detail::requireSize(registered, params.colour_width, params.colour_height, "registerDepthCpu", "registered");
  // The output is the z-buffer: 0 = empty, else the smallest depth that landed (the shader's
  // atomicMin on a uint per pixel, with 0xFFFFFFFF for empty, resolved to 0 afterwards).
  for (int y = 0; y < params.colour_height; ++y) {
    for (int x = 0; x < params.colour_width; ++x) registered(x, y) = 0;
  }
  for (int v = 0; v < params.depth_height; ++v) {
    for (int u = 0; u < params.depth_width; ++u) {
      const std::uint16_t d_units = raw(u, v);
      if (d_units == 0) continue;
      const float uf = static_cast<float>(u);
      const float vf = static_cast<float>(v);
      const float d = static_cast<float>(d_units);
      // Same operation order as the shader: ((h·u + h·v) + h), then d·ray + e.
      const float ray_x = params.h00 * uf + params.h01 * vf + params.h02;
      const float ray_y = params.h10 * uf + params.h11 * vf + params.h12;
      const float ray_z = params.h20 * uf + params.h21 * vf + params.h22;
      const float h_x = d * ray_x + params.e_x;
      const float h_y = d * ray_y + params.e_y;
      const float h_z = d * ray_z + params.e_z;
      // Behind or at the colour camera, or farther than a uint16 holds: dropped. h_z ≥ ½ also keeps the
      // rounded depth ≥ 1, so a landed point is never mistaken for "no depth".
      if (!(h_z >= 0.5f && h_z < kMaxRawDepth + 0.5f)) continue;
      const int x = nearestPixel(h_x, h_z, params.colour_width);
      const int y = nearestPixel(h_y, h_z, params.colour_height);
      if (x < 0 || y < 0) continue;
      const auto z_units = static_cast<std::uint16_t>(std::floor(h_z + 0.5f));
      std::uint16_t& target = registered(x, y);
      if (target == 0 || z_units < target) target = z_units;
    }
  }
}

}  // namespace vifusion::preprocess
