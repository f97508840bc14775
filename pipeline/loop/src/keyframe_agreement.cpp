#include "vifusion/loop/keyframe_agreement.hpp"

#include <cmath>

#include "vifusion/core/error.hpp"

namespace vifusion::loop {
namespace {

/// Below one grey level of standard deviation the compared pixels hold no texture beyond the 8-bit quantisation:
/// their correlation is rounding noise, and colour cannot tell [grey levels²].
constexpr double kMinLumaVariance = 1.0;

/// Rec. 601 luma [0, 255].
double luma(const Rgb8& c) { return 0.299 * c.r + 0.587 * c.g + 0.114 * c.b; }

}  // namespace

KeyframeAgreement keyframeAgreement(const FernImage& frame, const FernKeyframe& keyframe, const SE3d& T_K_C,
                                    const PinholeCamera& input_camera, int factor, double depth_gate_m) {
  if (factor < 1 || !(depth_gate_m > 0.0)) {
    throw Error("keyframe agreement: factor " + std::to_string(factor) + " must be >= 1 and the depth gate " +
                std::to_string(depth_gate_m) + " m > 0");
  }
  const int width = frame.width();
  const int height = frame.height();
  if (keyframe.rgb.width != width || keyframe.rgb.height != height || keyframe.depth_m.width != width ||
      keyframe.depth_m.height != height) {
    throw Error("keyframe agreement: the frame's and the keyframe's block images differ in size");
  }
  // Block (u, v)'s centre is input pixel u·f + (f − 1)/2 (fern_image.hpp).
  const double half_block = 0.5 * (factor - 1);
  const double f = factor;
  KeyframeAgreement agreement;
  double sum_a = 0.0, sum_b = 0.0, sum_aa = 0.0, sum_bb = 0.0, sum_ab = 0.0;
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      const double z_C = frame.depth_m(u, v);
      if (!(z_C > 0.0)) continue;
      ++agreement.frame_blocks;
      const Eigen::Vector3d p_C = input_camera.backProject({u * f + half_block, v * f + half_block}, z_C);
      const Eigen::Vector3d p_K = T_K_C * p_C;
      if (!(p_K.z() > 0.0)) continue;
      const Eigen::Vector2d uv_K = input_camera.project(p_K);
      const auto u_K = static_cast<int>(std::lround((uv_K.x() - half_block) / f));
      const auto v_K = static_cast<int>(std::lround((uv_K.y() - half_block) / f));
      if (u_K < 0 || u_K >= width || v_K < 0 || v_K >= height) continue;
      const double z_K = keyframe.depth_m(u_K, v_K);
      if (!(z_K > 0.0)) continue;
      ++agreement.overlap;
      if (std::abs(z_K - p_K.z()) > depth_gate_m) continue;
      ++agreement.depth_agreeing;
      const double a = luma(frame.rgb(u, v));
      const double b = luma(keyframe.rgb(u_K, v_K));
      sum_a += a;
      sum_b += b;
      sum_aa += a * a;
      sum_bb += b * b;
      sum_ab += a * b;
    }
  }
  const double n = agreement.depth_agreeing;
  if (n < 2.0) return agreement;
  const double var_a = std::max(0.0, sum_aa / n - (sum_a / n) * (sum_a / n));
  const double var_b = std::max(0.0, sum_bb / n - (sum_b / n) * (sum_b / n));
  agreement.frame_luma_std = std::sqrt(var_a);
  agreement.keyframe_luma_std = std::sqrt(var_b);
  // (Either side's texture within the quantisation leaves the correlation at 0.)
  if (var_a >= kMinLumaVariance && var_b >= kMinLumaVariance) {
    agreement.luma_ncc = (sum_ab / n - (sum_a / n) * (sum_b / n)) / std::sqrt(var_a * var_b);
  }
  return agreement;
}

}  // namespace vifusion::loop
