#pragma once
// Box-filtered building blocks of the procedural textures (texture.cpp): each returns the mean of a
// pattern over an interval of width `width` centred on the sample, so a texture built from them is the
// pattern integrated over the pixel's footprint, as a camera pixel integrates light, instead of a point
// sample that aliases whatever is finer than the pixel. Widths come from TextureFilter::width(), which
// matches the footprint's second moment (a box of width w has variance w²/12). With width 0 every
// function is the plain point sample, so the unfiltered texture is the same function.
//
// Filtering each building block and then combining them (products, blends) is exact for sums and
// only approximately right for products of overlapping patterns; the errors are confined to pixels
// where two filtered features overlap and are far smaller than the aliasing they replace.

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "vifusion/scene/counter_rng.hpp"

namespace vifusion::scene::texture_filter {

/// The pixel footprint of one sample in texture coordinates.
class TextureFilter {
 public:
  /// J_st_px: st offset [m] per pixel offset [px] (zero: point sample).
  explicit TextureFilter(const Eigen::Matrix2d& J_st_px)
      : J_st_px_(J_st_px), s_width_m_(J_st_px.row(0).norm()), t_width_m_(J_st_px.row(1).norm()) {}

  /// Box width [units of g] of a quantity g with gradient (dg/ds, dg/dt) [units of g per m] over the
  /// footprint: ‖J_st_pxᵀ·∇g‖, the width of the box with the same variance as g over the pixel square.
  double width(double dg_ds, double dg_dt) const {
    return (J_st_px_.transpose() * Eigen::Vector2d(dg_ds, dg_dt)).norm();
  }
  double sWidth() const { return s_width_m_; }  ///< width(1, 0) [m]
  double tWidth() const { return t_width_m_; }  ///< width(0, 1) [m]

 private:
  Eigen::Matrix2d J_st_px_;
  double s_width_m_;
  double t_width_m_;
};

/// Widths below this [units of the variable: m or rad] are point samples: the differences of
/// antiderivatives below would lose their precision to rounding of the ~10 m coordinates.
inline constexpr double kPointWidth = 1e-9;

// The small building blocks are inline: they run several times per pixel with constant periods and
// edges that the compiler folds.

/// Position of x inside the current period, in [0, period).
inline double wrap(double x, double period) { return x - period * std::floor(x / period); }

/// Fraction of [x − width/2, x + width/2] inside [lo, hi) (lo may be −∞, hi +∞).
inline float interval(double x, double lo, double hi, double width) {
  if (!(width > kPointWidth)) return x >= lo && x < hi ? 1.0F : 0.0F;
  const double a = std::clamp(x - 0.5 * width, lo, hi);
  const double b = std::clamp(x + 0.5 * width, lo, hi);
  return static_cast<float>((b - a) / width);
}

/// Fraction of [x − width/2, x + width/2] inside the periodic set {y : lo ≤ y mod period < hi},
/// 0 ≤ lo < hi ≤ period.
inline float pulseTrain(double x, double period, double lo, double hi, double width) {
  if (!(width > kPointWidth)) {
    const double r = wrap(x, period);
    return (lo <= 0.0 || r >= lo) && r < hi ? 1.0F : 0.0F;  // lo = 0 also takes a rounded −0.0…01
  }
  // In units of the period: whole periods between the ends of the interval times the duty, plus the
  // covered parts of the two partial periods (an integer count, so no large values cancel).
  const double inverse_period = 1.0 / period;
  const double a = (x - 0.5 * width) * inverse_period;
  const double b = (x + 0.5 * width) * inverse_period;
  const double lo_p = lo * inverse_period;
  const double duty_p = (hi - lo) * inverse_period;
  const double a0 = std::floor(a);
  const double b0 = std::floor(b);
  const double covered =
      (b0 - a0) * duty_p + std::clamp(b - b0 - lo_p, 0.0, duty_p) - std::clamp(a - a0 - lo_p, 0.0, duty_p);
  return static_cast<float>(covered * period / width);
}

/// Fraction of the interval where ⌊x / period⌋ is odd (stripes and checks).
inline float oddCells(double x, double period, double width) {
  return pulseTrain(x, 2.0 * period, period, 2.0 * period, width);
}

/// Mean of sin(phase) over [phase − width/2, phase + width/2] [rad]: sin(phase)·sinc(width/2).
inline float sinMean(double phase_rad, double width_rad) {
  const double half = 0.5 * width_rad;
  const double sinc = half > 1e-6 ? std::sin(half) / half : 1.0;  // 1 − half²/6 ≈ 1 below
  return static_cast<float>(std::sin(phase_rad) * sinc);
}

/// Uniform [0, 1) value attached to the integer lattice point (i, j) of one noise layer: the bits of
/// counterBits(layer, 0x7e7, (i, j)) (counter_rng.hpp) with the layer's two outer mixes done once.
class NoiseLattice {
 public:
  explicit NoiseLattice(std::uint32_t layer) : key_(mix64(mix64(layer + 0x9e3779b97f4a7c15ULL) ^ 0x7e7u)) {}
  float operator()(std::int64_t i, std::int64_t j) const {
    const std::uint64_t counter =
        (static_cast<std::uint64_t>(static_cast<std::uint32_t>(i)) << 32) | static_cast<std::uint32_t>(j);
    return static_cast<float>(mix64(key_ ^ counter) >> 40) * 0x1.0p-24F;
  }

 private:
  std::uint64_t key_;
};

/// Value noise in [0, 1) with features of size scale_m (smoothstep-interpolated lattice, C¹), averaged
/// over the box s ± width_s_m/2, t ± width_t_m/2 (exact: the interpolation weights are integrated;
/// boxes under a tenth of a cell, where that changes nothing visible, take the point sample).
/// Boxes wider than two lattice cells are averaged over two and the deviation from the mean 0.5 is
/// scaled by √(2 / cells) per axis, the fall-off of the mean of a process with unit correlation
/// length, which keeps the cost bounded where a grazing view squeezes many cells into one pixel.
float valueNoise(double s_m, double t_m, double scale_m, std::uint32_t layer, double width_s_m = 0.0,
                 double width_t_m = 0.0);

}  // namespace vifusion::scene::texture_filter
