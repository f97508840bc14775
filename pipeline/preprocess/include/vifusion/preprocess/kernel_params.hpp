#pragma once
// Push-constant blocks of the preprocessing shaders (shaders/*.comp), mirrored member for member.
// The host pushes these structs verbatim and the CPU references take the same structs, so a
// parameter cannot mean one thing on the GPU and another on the CPU. Only 4-byte members
// (std::int32_t ↔ int, float ↔ float), so the std430 push-constant offsets are 0, 4, 8, … with no
// padding; the static_asserts below pin every offset against the GLSL declaration order.

#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "vifusion/core/pinhole_camera.hpp"

namespace vifusion::preprocess {

/// Push-constant space every Vulkan device guarantees (maxPushConstantsSize ≥ 128).
inline constexpr std::size_t kMaxPushConstantBytes = 128;

/// Workgroup size the shaders declare when specialization constants 0 (x) and 1 (y) are not set.
inline constexpr std::uint32_t kDefaultWorkgroupSize = 16;

/// Separable 5-tap Gaussian (binomial 1 4 6 4 1 / 16) of both pyramids; mirrors kPyramidWeights in
/// shaders/include/preprocess/common.glsl. Weights and their products are exact in float; they sum to 1.
inline constexpr float kPyramidWeights[5] = {0.0625f, 0.25f, 0.375f, 0.25f, 0.0625f};

/// depth_to_metric.comp: raw uint16 depth → metres, gated to [min_depth_m, max_depth_m]. The sensor's
/// systematic error is removed first: z = z_raw / (1 − b·z_raw), z_raw = raw·depth_scale_m, which is
/// 1/z = 1/z_raw − b (RigCalibration::inverse_depth_bias_per_m); b = 0 leaves z_raw bit for bit.
struct DepthToMetricParams {
  std::int32_t width = 0;        ///< image width [px]
  std::int32_t height = 0;       ///< image height [px]
  float depth_scale_m = 0.001f;  ///< metres per raw unit: 0.001 for millimetre sensors, 1/5000 for TUM/ICL-NUIM
  float min_depth_m = 0.3f;      ///< smallest kept depth [m], inclusive (after the correction)
  float max_depth_m = 4.0f;      ///< largest kept depth [m], inclusive (after the correction)
  float inverse_depth_bias_per_m = 0.0f;  ///< b: the sensor's 1/z reads b too high [1/m]
};

/// bilateral_depth.comp: edge-preserving depth smoothing. Window and σ_space are ElasticFusion's;
/// the range σ follows the sensor's axial noise at the centre pixel's depth z instead of
/// ElasticFusion's fixed 30 mm: σ_range(z) = range_sigmas · (noise_a_m + noise_b_per_m·(z − noise_z0_m)²).
/// Structured-light depth is quantised in disparity, so its steps grow with z² (≈ 3 mm at 1 m,
/// ≈ 50 mm at 4 m): a fixed σ either leaves the far steps (and the normals from them) intact or
/// rounds every near edge. The noise model is the one the ICP weights use (IcpOptions).
///
/// OFF by default (radius 0: a copy). Tracking raw vertices with normals from central differences
/// over a fixed viewing angle (PreprocessOptions::normal_span_rad) beat every filter setting we
/// measured on ICL-NUIM-noise frames: the filter rounds corners differently from each viewpoint and
/// that bias, not the noise, dominated the error (640×480, 30 noise-free frames, ICP only: 1–4 mm
/// unfiltered vs 15 mm with the filter). radius 6 gives ElasticFusion's 13 × 13 window.
struct BilateralDepthParams {
  std::int32_t width = 0;         ///< image width [px]
  std::int32_t height = 0;        ///< image height [px]
  std::int32_t radius_px = 0;     ///< window half-size [px], ≥ 0: 0 = off, 6 = ElasticFusion's 13 × 13
  float sigma_space_px = 4.5f;    ///< spatial standard deviation [px], > 0
  float range_sigmas = 3.0f;      ///< σ_range in units of the axial noise σ_z(z) [1], > 0
  float noise_a_m = 0.0012f;      ///< σ_z(z) = a + b·(z − z0)² (Nguyen et al. 2012, Kinect) [m]
  float noise_b_per_m = 0.0019f;  ///< [1/m]
  float noise_z0_m = 0.4f;        ///< [m]
};

/// pyramid_down_depth.comp: (src_width, src_height) → (src_width/2, src_height/2), floor.
struct PyramidDownDepthParams {
  std::int32_t src_width = 0;   ///< fine-level width [px]
  std::int32_t src_height = 0;  ///< fine-level height [px]
  float range_gate_m = 0.09f;   ///< neighbours farther than this from the centre depth are not averaged
                                ///< [m], inclusive; 3·σ_range with σ_range = 0.03 m
};

/// pyramid_down_intensity.comp: (src_width, src_height) → (src_width/2, src_height/2), floor.
struct PyramidDownIntensityParams {
  std::int32_t src_width = 0;   ///< fine-level width [px]
  std::int32_t src_height = 0;  ///< fine-level height [px]
};

/// rgb_to_intensity.comp: intensity = weight_r·R + weight_g·G + weight_b·B on the 0..255 scale.
/// Defaults are Rec. 601 luma; ElasticFusion's permuted weights are deliberately not used.
/// A BGR source swaps weight_r and weight_b (the weights apply to bytes 0, 1, 2 of each pixel).
struct RgbToIntensityParams {
  std::int32_t width = 0;   ///< image width [px]
  std::int32_t height = 0;  ///< image height [px]
  float weight_r = 0.299f;  ///< weight of byte 0 of each pixel [1]
  float weight_g = 0.587f;  ///< weight of byte 1 [1]
  float weight_b = 0.114f;  ///< weight of byte 2 [1]
};

/// vertex_map.comp: pinhole back-projection of metric depth. No default intrinsics: set them
/// (fromCamera) for the pyramid level being processed.
struct VertexMapParams {
  std::int32_t width = 0;   ///< image width [px]
  std::int32_t height = 0;  ///< image height [px]
  float fx = 0.0f;          ///< focal length along u [px]
  float fy = 0.0f;          ///< focal length along v [px]; may be negative (ICL-NUIM)
  float cx = 0.0f;          ///< principal point u [px], pixel centres at integer coordinates
  float cy = 0.0f;          ///< principal point v [px]

  /// Intrinsics of `camera` (already at the wanted pyramid level, e.g. camera.atLevel(l)), in float.
  static VertexMapParams fromCamera(const PinholeCamera& camera) {
    return {camera.width,
            camera.height,
            static_cast<float>(camera.fx),
            static_cast<float>(camera.fy),
            static_cast<float>(camera.cx),
            static_cast<float>(camera.cy)};
  }
};

/// normal_map.comp: normals from central differences span_px pixels either side,
/// n ∝ (v(x+s, y) − v(x−s, y)) × (v(x, y+s) − v(x, y−s)).
struct NormalMapParams {
  std::int32_t width = 0;   ///< image width [px]
  std::int32_t height = 0;  ///< image height [px]
  /// Smallest accepted |a × b| [m²] (the area spanned by the two differences). A
  /// fronto-parallel pixel footprint at the nearest gated depth (0.3 m, f ≈ 500 px) spans
  /// ≈ 4e-7 m², so 1e-12 m² rejects only coincident or collinear neighbours, never a real
  /// (even grazing) surface. Compared squared; keep it ≥ 1e-18 so that the square stays a
  /// normal float on GPUs that flush denormals.
  float min_cross_norm_m2 = 1e-12f;
  std::int32_t span_px = 1;  ///< s ≥ 1: half the baseline of each difference [px]
};

/// intensity_gradient.comp: Sobel 3 × 3 / 8 with border replicate.
struct IntensityGradientParams {
  std::int32_t width = 0;   ///< image width [px]
  std::int32_t height = 0;  ///< image height [px]
};

/// register_depth.comp (both passes): raw depth of the depth camera D → raw depth in the pixels of the
/// colour camera C, same units. The whole warp of depth pixel (u, v) with raw depth d [units] is one
/// homogeneous map h = d·(H·(u, v, 1)ᵀ) + e with H = K_C·R_C_D·K_D⁻¹ [1] and e = K_C·t_C_D / depth_scale
/// [units·px]: the colour pixel is (h_x/h_z, h_y/h_z) and h_z is the depth along C's optical axis
/// [units]. Working in raw units rather than metres leaves no division in the depth (it is h_z itself)
/// and one rounding to the output's integer units. Built by DepthRegistration::kernelParams() in double
/// and rounded to float once, so the shader and registerDepthCpu read the same floats.
struct RegisterDepthParams {
  std::int32_t depth_width = 0;              ///< input (depth camera) width [px]
  std::int32_t depth_height = 0;             ///< input height [px]
  std::int32_t colour_width = 0;             ///< output (colour camera) width [px], even (packed 2 pixels a word)
  std::int32_t colour_height = 0;            ///< output height [px]
  float h00 = 1.0f, h01 = 0.0f, h02 = 0.0f;  ///< H row 0 [1, 1, px]
  float h10 = 0.0f, h11 = 1.0f, h12 = 0.0f;  ///< H row 1 [1, 1, px]
  float h20 = 0.0f, h21 = 0.0f, h22 = 1.0f;  ///< H row 2 [1/px, 1/px, 1]
  float e_x = 0.0f;                          ///< K_C·t_C_D / depth_scale, x [units·px]
  float e_y = 0.0f;                          ///< y [units·px]
  float e_z = 0.0f;                          ///< z: the baseline along C's optical axis [units]
};

// Layout pins: offsets follow the GLSL member order, 4 bytes per member.
template <typename T>
inline constexpr bool kIsPushConstantBlock = std::is_standard_layout_v<T>&& std::is_trivially_copyable_v<T> &&
                                             sizeof(T) % 4 == 0 && sizeof(T) <= kMaxPushConstantBytes;

static_assert(kIsPushConstantBlock<DepthToMetricParams>);
static_assert(sizeof(DepthToMetricParams) == 24);
static_assert(offsetof(DepthToMetricParams, depth_scale_m) == 8);
static_assert(offsetof(DepthToMetricParams, min_depth_m) == 12);
static_assert(offsetof(DepthToMetricParams, max_depth_m) == 16);
static_assert(offsetof(DepthToMetricParams, inverse_depth_bias_per_m) == 20);

static_assert(kIsPushConstantBlock<BilateralDepthParams>);
static_assert(sizeof(BilateralDepthParams) == 32);
static_assert(offsetof(BilateralDepthParams, radius_px) == 8);
static_assert(offsetof(BilateralDepthParams, sigma_space_px) == 12);
static_assert(offsetof(BilateralDepthParams, range_sigmas) == 16);
static_assert(offsetof(BilateralDepthParams, noise_a_m) == 20);
static_assert(offsetof(BilateralDepthParams, noise_b_per_m) == 24);
static_assert(offsetof(BilateralDepthParams, noise_z0_m) == 28);

static_assert(kIsPushConstantBlock<PyramidDownDepthParams>);
static_assert(sizeof(PyramidDownDepthParams) == 12);
static_assert(offsetof(PyramidDownDepthParams, range_gate_m) == 8);

static_assert(kIsPushConstantBlock<PyramidDownIntensityParams>);
static_assert(sizeof(PyramidDownIntensityParams) == 8);

static_assert(kIsPushConstantBlock<RgbToIntensityParams>);
static_assert(sizeof(RgbToIntensityParams) == 20);
static_assert(offsetof(RgbToIntensityParams, weight_r) == 8);
static_assert(offsetof(RgbToIntensityParams, weight_g) == 12);
static_assert(offsetof(RgbToIntensityParams, weight_b) == 16);

static_assert(kIsPushConstantBlock<VertexMapParams>);
static_assert(sizeof(VertexMapParams) == 24);
static_assert(offsetof(VertexMapParams, fx) == 8);
static_assert(offsetof(VertexMapParams, fy) == 12);
static_assert(offsetof(VertexMapParams, cx) == 16);
static_assert(offsetof(VertexMapParams, cy) == 20);

static_assert(kIsPushConstantBlock<NormalMapParams>);
static_assert(sizeof(NormalMapParams) == 16);
static_assert(offsetof(NormalMapParams, min_cross_norm_m2) == 8);
static_assert(offsetof(NormalMapParams, span_px) == 12);

static_assert(kIsPushConstantBlock<IntensityGradientParams>);
static_assert(sizeof(IntensityGradientParams) == 8);

static_assert(kIsPushConstantBlock<RegisterDepthParams>);
static_assert(sizeof(RegisterDepthParams) == 64);
static_assert(offsetof(RegisterDepthParams, colour_width) == 8);
static_assert(offsetof(RegisterDepthParams, h00) == 16);
static_assert(offsetof(RegisterDepthParams, h22) == 48);
static_assert(offsetof(RegisterDepthParams, e_x) == 52);
static_assert(offsetof(RegisterDepthParams, e_z) == 60);

}  // namespace vifusion::preprocess
