#include "texture_filter.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace vifusion::scene::texture_filter {
namespace {

/// Noise boxes narrower than this [lattice cells] are point samples: the box mean of the C¹ noise
/// differs from its centre value by about width²/24 times its second derivative (at most 6 per cell²),
/// under 0.15 grey levels for any of the textures' amplitudes.
constexpr double kSmoothNoiseCells = 0.1;

/// Noise boxes are integrated over at most this many lattice cells per axis (4 taps).
constexpr double kMaxNoiseCells = 2.0;
constexpr int kMaxTaps = 4;

/// Antiderivative of the value-noise interpolation kernel φ(y) = 1 − smoothstep(|y|) on [−1, 1]
/// (0 before, 1 after): Φ(y) = ½ + y − y³ + y³·|y|/2, which is 0 and 1 at y = ∓1, so clamping y
/// extends it without branches.
double kernelIntegral(double y) {
  y = std::clamp(y, -1.0, 1.0);
  const double y3 = y * y * y;
  return 0.5 + y - y3 + 0.5 * y3 * std::abs(y);
}

/// Interpolation weights of lattice points first, first + 1, … along one axis, in lattice units.
struct AxisTaps {
  std::int64_t first = 0;
  int count = 0;
  std::array<double, kMaxTaps> weight{};
  double attenuation = 1.0;  ///< scale of the deviation from the mean for boxes beyond kMaxNoiseCells
};

AxisTaps axisTaps(double x, double width) {
  AxisTaps taps;
  if (width < kSmoothNoiseCells) {
    const double x0 = std::floor(x);
    const double f = x - x0;
    const double w = f * f * (3.0 - 2.0 * f);
    taps.first = static_cast<std::int64_t>(x0);
    taps.count = 2;
    taps.weight = {1.0 - w, w, 0.0, 0.0};
    return taps;
  }
  if (width > kMaxNoiseCells) {
    taps.attenuation = std::sqrt(kMaxNoiseCells / width);
    width = kMaxNoiseCells;
  }
  const double a = x - 0.5 * width;
  const double b = x + 0.5 * width;
  const double first = std::floor(a);
  const double inverse_width = 1.0 / width;
  taps.first = static_cast<std::int64_t>(first);
  taps.count = std::min(kMaxTaps, static_cast<int>(std::ceil(b) - first) + 1);
  for (int k = 0; k < taps.count; ++k) {
    const double centre = first + k;
    taps.weight[static_cast<std::size_t>(k)] =
        (kernelIntegral(b - centre) - kernelIntegral(a - centre)) * inverse_width;
  }
  return taps;
}

}  // namespace

float valueNoise(double s_m, double t_m, double scale_m, std::uint32_t layer, double width_s_m, double width_t_m) {
  const NoiseLattice lattice(layer);
  const double s = s_m / scale_m;
  const double t = t_m / scale_m;
  const double width_s = width_s_m / scale_m;
  const double width_t = width_t_m / scale_m;
  if (width_s < kSmoothNoiseCells && width_t < kSmoothNoiseCells) {
    // Point sample: bilinear blend of the four corners with smoothstep weights.
    const double s0 = std::floor(s);
    const double t0 = std::floor(t);
    const auto i = static_cast<std::int64_t>(s0);
    const auto j = static_cast<std::int64_t>(t0);
    const auto fs = static_cast<float>(s - s0);
    const auto ft = static_cast<float>(t - t0);
    const float ws = fs * fs * (3.0F - 2.0F * fs);
    const float wt = ft * ft * (3.0F - 2.0F * ft);
    const float bottom = lattice(i, j) + ws * (lattice(i + 1, j) - lattice(i, j));
    const float top = lattice(i, j + 1) + ws * (lattice(i + 1, j + 1) - lattice(i, j + 1));
    return bottom + wt * (top - bottom);
  }
  // The noise is Σ L(i, j)·φ(s − i)·φ(t − j), so its box mean is the same sum with each φ replaced by
  // its mean over the box's extent along that axis.
  const AxisTaps along_s = axisTaps(s, width_s);
  const AxisTaps along_t = axisTaps(t, width_t);
  double sum = 0.0;
  for (int b = 0; b < along_t.count; ++b) {
    double row = 0.0;
    for (int a = 0; a < along_s.count; ++a) {
      row += along_s.weight[static_cast<std::size_t>(a)] * lattice(along_s.first + a, along_t.first + b);
    }
    sum += along_t.weight[static_cast<std::size_t>(b)] * row;
  }
  return static_cast<float>(0.5 + (sum - 0.5) * along_s.attenuation * along_t.attenuation);
}

}  // namespace vifusion::scene::texture_filter
