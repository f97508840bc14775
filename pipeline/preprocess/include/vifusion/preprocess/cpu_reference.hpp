#pragma once
// CPU references of the preprocessing shaders (shaders/*.comp): the same formulas, operation order
// and border rules in float arithmetic, so GPU results can be compared pixel by pixel. Each takes
// the shader's push-constant struct; the views' sizes must match it (std::invalid_argument
// otherwise). No allocation, single-threaded, any row stride.
//
// Where GPU and CPU may still differ (Vulkan precision rules, SPIR-V environment spec):
//  - exp (bilateral) may be off by 3 + 2·|x| ULP on the GPU, ≤ 1 ULP in glibc;
//  - division and sqrt are ≤ 2.5 ULP on the GPU, correctly rounded on the CPU
//    (bilateral, pyramid_down_depth, vertex_map, normal_map);
//  - a·b + c may be fused into one FMA (rgb_to_intensity, the weighted sums of bilateral and the
//    pyramids, cross products):
//    GPU compilers may do so freely, GCC in ISO C++ mode does not, clang does on FMA targets (aarch64);
//  - GPUs may flush denormals to zero (only negligible bilateral weights get that small).
// depth_to_metric and intensity_gradient are exact on any conforming device (one rounding per
// operation, and the only fusable a + 2·b is exact); so is register_depth (its sums are `precise` and
// its division only proposes a pixel, see registerDepthCpu). On lavapipe (Mesa 22.3) every kernel except
// bilateral_depth matched bit for bit; bilateral_depth differed by ≤ 6e-7 relative (exp).
// Compare normals with an absolute tolerance: components near 0 have no meaningful relative error.

#include <cstdint>

#include "vifusion/core/image.hpp"
#include "vifusion/preprocess/kernel_params.hpp"
#include "vifusion/preprocess/pixel_types.hpp"

namespace vifusion::preprocess {

/// depth_to_metric.comp. raw: sensor units; depth_m: [m], 0 = invalid.
void depthToMetricCpu(ImageView<const std::uint16_t> raw, const DepthToMetricParams& params, ImageView<float> depth_m);

/// bilateral_depth.comp. depth_m, filtered_m: [m], 0 = invalid; must not alias.
void bilateralDepthCpu(ImageView<const float> depth_m, const BilateralDepthParams& params, ImageView<float> filtered_m);

/// pyramid_down_depth.comp. fine_m: src_width × src_height; coarse_m: (src_width/2) × (src_height/2).
void pyramidDownDepthCpu(ImageView<const float> fine_m, const PyramidDownDepthParams& params,
                         ImageView<float> coarse_m);

/// pyramid_down_intensity.comp. fine: src_width × src_height; coarse: (src_width/2) × (src_height/2).
void pyramidDownIntensityCpu(ImageView<const float> fine, const PyramidDownIntensityParams& params,
                             ImageView<float> coarse);

/// rgb_to_intensity.comp. intensity: [0..255].
void rgbToIntensityCpu(ImageView<const Rgb8> rgb, const RgbToIntensityParams& params, ImageView<float> intensity);

/// vertex_map.comp. depth_m: [m], 0 = invalid; vertices: (x, y, z, 1) [m], Zero() = invalid.
void vertexMapCpu(ImageView<const float> depth_m, const VertexMapParams& params, ImageView<VertexPixel> vertices);

/// normal_map.comp. vertices: invalid where z ≤ 0; normals: unit, n·v < 0, Zero() = invalid.
void normalMapCpu(ImageView<const VertexPixel> vertices, const NormalMapParams& params, ImageView<NormalPixel> normals);

/// register_depth.comp (scatter and resolve passes): raw: depth_width × depth_height [units],
/// 0 = invalid; registered: colour_width × colour_height [the same units], 0 = nothing landed; must not
/// alias. Exact on any conforming device: only correctly rounded + and · feed a decision (FMA
/// contraction is off on both sides), and the one division only proposes a pixel that exact
/// comparisons then confirm (see the shader).
void registerDepthCpu(ImageView<const std::uint16_t> raw, const RegisterDepthParams& params,
                      ImageView<std::uint16_t> registered);

/// intensity_gradient.comp. gradient: (∂I/∂u, ∂I/∂v) [intensity / px].
void intensityGradientCpu(ImageView<const float> intensity, const IntensityGradientParams& params,
                          ImageView<GradientPixel> gradient);

}  // namespace vifusion::preprocess
