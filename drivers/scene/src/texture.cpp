#include "vifusion/scene/texture.hpp"

#include <cmath>
#include <numbers>

#include "vifusion/scene/counter_rng.hpp"

namespace vifusion::scene {
namespace {

Albedo rgb(int r, int g, int b) {
  return Albedo(static_cast<float>(r), static_cast<float>(g), static_cast<float>(b)) / 255.0F;
}

/// Uniform [0, 1) value attached to the integer lattice point (i, j) of texture layer `layer`.
float lattice(std::int64_t i, std::int64_t j, std::uint32_t layer) {
  const std::uint64_t key =
      (static_cast<std::uint64_t>(static_cast<std::uint32_t>(i)) << 32) | static_cast<std::uint32_t>(j);
  return static_cast<float>(counterBits(layer, 0x7e7u, key) >> 40) * 0x1.0p-24F;
}

/// Smooth value noise in [0, 1) with features of size `scale_m` (C¹ across cells, so gradients stay finite).
float valueNoise(double s_m, double t_m, double scale_m, std::uint32_t layer) {
  const double s = s_m / scale_m;
  const double t = t_m / scale_m;
  const double s0 = std::floor(s);
  const double t0 = std::floor(t);
  const auto i = static_cast<std::int64_t>(s0);
  const auto j = static_cast<std::int64_t>(t0);
  const auto fs = static_cast<float>(s - s0);
  const auto ft = static_cast<float>(t - t0);
  const float ws = fs * fs * (3.0F - 2.0F * fs);
  const float wt = ft * ft * (3.0F - 2.0F * ft);
  const float bottom = lattice(i, j, layer) + ws * (lattice(i + 1, j, layer) - lattice(i, j, layer));
  const float top = lattice(i, j + 1, layer) + ws * (lattice(i + 1, j + 1, layer) - lattice(i, j + 1, layer));
  return bottom + wt * (top - bottom);
}

/// Multiplicative modulation 1 + amplitude·(2n − 1) from value noise n.
float grain(double s_m, double t_m, double scale_m, float amplitude, std::uint32_t layer) {
  return 1.0F + amplitude * (2.0F * valueNoise(s_m, t_m, scale_m, layer) - 1.0F);
}

int parity(double s_m, double period_m) { return static_cast<int>(std::floor(s_m / period_m)) & 1; }

/// Position inside the current period, in [0, period_m).
double wrap(double s_m, double period_m) { return s_m - period_m * std::floor(s_m / period_m); }

/// Deterministic palette pick: hash of (variant, salt) in [0, 1).
float pick(std::uint32_t variant, std::uint32_t salt) {
  return static_cast<float>(counterBits(variant, salt, 0x5eedu) >> 40) * 0x1.0p-24F;
}

Albedo wallStripes(double s, double t) {
  // Coarse: 45 cm stripes in two tones with a thin dark pinstripe at each border.
  Albedo base = parity(s, 0.45) ? rgb(204, 189, 148) : rgb(140, 168, 148);
  if (wrap(s, 0.45) < 0.012) base *= 0.6F;
  // Medium: 9 cm checks of slightly different lightness.
  if (parity(s, 0.09) ^ parity(t, 0.09)) base *= 0.9F;
  // Fine: paper grain.
  return base * grain(s, t, 0.012, 0.08F, 1);
}

Albedo wallPanels(double s, double t) {
  constexpr double kRailLow_m = 0.9;
  constexpr double kRailHigh_m = 0.96;
  if (t < kRailLow_m) {
    // Wainscot: 55 cm panels framed by 6 cm stiles with 1.5 cm grooves at the panel edges.
    const double u = wrap(s, 0.55);
    const double v = t;
    const bool stile = u < 0.06 || v < 0.08 || v > kRailLow_m - 0.06;
    Albedo base = stile ? rgb(168, 148, 122) : rgb(199, 184, 158);
    const bool groove = (u >= 0.06 && u < 0.075) || (v >= 0.08 && v < 0.095);
    if (groove) base *= 0.7F;
    return base * grain(s, t, 0.015, 0.06F, 2);
  }
  if (t < kRailHigh_m) return rgb(120, 90, 62) * grain(s, t, 0.02, 0.1F, 3);
  // Plaster: coarse blotches, medium mottling, fine stipple.
  const float coarse = grain(s, t, 0.6, 0.12F, 4);
  const float medium = grain(s, t, 0.12, 0.12F, 5);
  const float fine = grain(s, t, 0.012, 0.07F, 6);
  return rgb(148, 163, 184) * coarse * medium * fine;
}

Albedo wallBricks(double s, double t) {
  constexpr double kCourse_m = 0.085;
  constexpr double kBrick_m = 0.25;
  constexpr double kMortar_m = 0.012;
  const auto row = static_cast<std::int64_t>(std::floor(t / kCourse_m));
  const double shifted = s + ((row & 1) != 0 ? 0.5 * kBrick_m : 0.0);
  const auto column = static_cast<std::int64_t>(std::floor(shifted / kBrick_m));
  if (wrap(shifted, kBrick_m) < kMortar_m || wrap(t, kCourse_m) < kMortar_m) {
    return rgb(190, 186, 178) * grain(s, t, 0.01, 0.06F, 7);
  }
  const float tone = 0.8F + 0.35F * lattice(row, column, 8);
  return rgb(158, 84, 61) * tone * grain(s, t, 0.7, 0.1F, 9) * grain(s, t, 0.015, 0.08F, 10);
}

Albedo floorPlanks(double s, double t) {
  constexpr double kWidth_m = 0.16;
  constexpr double kLength_m = 1.25;
  constexpr double kGap_m = 0.004;
  const auto row = static_cast<std::int64_t>(std::floor(t / kWidth_m));
  const double along = s + 1.37 * lattice(row, 0, 11);  // staggered joints
  const auto plank = static_cast<std::int64_t>(std::floor(along / kLength_m));
  if (wrap(t, kWidth_m) < kGap_m || wrap(along, kLength_m) < kGap_m) return rgb(60, 40, 25);
  const float tone = 0.75F + 0.4F * lattice(row, plank, 12);
  // Grain: lines along the board, wavering with low-frequency noise.
  const double phase = t / 0.018 + 1.5 * valueNoise(along, t, 0.35, 13);
  const float lines = 0.9F + 0.1F * static_cast<float>(std::sin(2.0 * std::numbers::pi * phase));
  return rgb(140, 97, 56) * tone * lines * grain(along, t, 0.01, 0.05F, 14);
}

Albedo ceiling(double s, double t) {
  constexpr double kTile_m = 0.6;
  constexpr double kLine_m = 0.015;
  if (wrap(s, kTile_m) < kLine_m || wrap(t, kTile_m) < kLine_m) return rgb(170, 170, 165);
  return rgb(220, 217, 209) * grain(s, t, 0.1, 0.05F, 15) * grain(s, t, 0.015, 0.06F, 16);
}

Albedo rug(double s, double t) {
  const double ds = std::abs(wrap(s, 0.2) - 0.1);
  const double dt = std::abs(wrap(t, 0.2) - 0.1);
  Albedo base = ds + dt < 0.06 ? rgb(196, 160, 90) : rgb(128, 36, 40);
  if (parity(s, 0.6)) base = base.cwiseProduct(rgb(150, 170, 235));  // navy bands
  return base * grain(s, t, 0.01, 0.1F, 17);
}

Albedo fabric(std::uint32_t variant, double s, double t) {
  const Albedo base =
      Albedo(0.25F + 0.5F * pick(variant, 1), 0.2F + 0.4F * pick(variant, 2), 0.2F + 0.5F * pick(variant, 3));
  const bool band_s = wrap(s, 0.14) < 0.035;
  const bool band_t = wrap(t, 0.14) < 0.035;
  Albedo colour = base;
  if (band_s || band_t) colour *= 0.72F;
  if (band_s && band_t) colour *= 0.8F;
  if (std::abs(wrap(s, 0.14) - 0.08) < 0.004 || std::abs(wrap(t, 0.14) - 0.08) < 0.004) colour = rgb(225, 215, 160);
  return colour * grain(s, t, 0.4, 0.06F, 18) * grain(s, t, 0.008, 0.08F, 19);
}

Albedo wood(std::uint32_t variant, double s, double t) {
  static const Albedo kTones[] = {rgb(158, 115, 72), rgb(107, 72, 46), rgb(190, 158, 115)};
  const Albedo& tone = kTones[variant % 3];
  const double phase = t / 0.025 + 2.0 * valueNoise(s, t, 0.3, 20 + variant);
  const float lines = 0.88F + 0.12F * static_cast<float>(std::sin(2.0 * std::numbers::pi * phase));
  return tone * lines * grain(s, t, 0.01, 0.05F, 23);
}

Albedo paintedWood(std::uint32_t variant, double s, double t) {
  static const Albedo kPaints[] = {rgb(222, 216, 200), rgb(86, 120, 140), rgb(176, 98, 64), rgb(110, 130, 90)};
  Albedo paint = kPaints[variant % 4];
  if (wrap(s, 0.3) < 0.01 || wrap(t, 0.45) < 0.01) paint *= 0.65F;  // panel grooves
  return paint * grain(s, t, 0.08, 0.05F, 24) * grain(s, t, 0.012, 0.04F, 25);
}

Albedo book(std::uint32_t variant, double s, double t) {
  Albedo cover(0.15F + 0.7F * pick(variant, 4), 0.1F + 0.6F * pick(variant, 5), 0.1F + 0.6F * pick(variant, 6));
  const double band = wrap(t, 0.12);
  if (band > 0.02 && band < 0.035) cover = rgb(214, 180, 90);  // title bands
  return cover * grain(s, t, 0.01, 0.05F, 26);
}

Albedo canvas(std::uint32_t variant, double s, double t) {
  // Low-frequency interference pattern (the composition) plus medium brush strokes.
  const double a = 4.0 + 8.0 * pick(variant, 7);
  const double b = 4.0 + 8.0 * pick(variant, 8);
  const double phase = 6.3 * pick(variant, 9);
  const auto wave = [&](double fs, double ft, double offset) {
    return static_cast<float>(0.5 + 0.5 * std::sin(fs * s + ft * t + phase + offset));
  };
  const Albedo colour(0.15F + 0.75F * wave(a, 0.5 * b, 0.0), 0.15F + 0.7F * wave(-0.7 * a, b, 2.0),
                      0.15F + 0.7F * wave(0.4 * a, -0.9 * b, 4.0));
  return colour * grain(s, t, 0.03, 0.12F, 27) * grain(s, t, 0.01, 0.05F, 28);
}

}  // namespace

Albedo albedo(Material material, std::uint32_t variant, const Eigen::Vector2d& st_m) {
  const double s = st_m.x();
  const double t = st_m.y();
  switch (material) {
    case Material::kWallStripes:
      return wallStripes(s, t);
    case Material::kWallPanels:
      return wallPanels(s, t);
    case Material::kWallBricks:
      return wallBricks(s, t);
    case Material::kWhiteWall:
      return rgb(235, 235, 235);
    case Material::kFloorPlanks:
      return floorPlanks(s, t);
    case Material::kCeiling:
      return ceiling(s, t);
    case Material::kRug:
      return rug(s, t);
    case Material::kFabric:
      return fabric(variant, s, t);
    case Material::kWood:
      return wood(variant, s, t);
    case Material::kPaintedWood:
      return paintedWood(variant, s, t);
    case Material::kBook:
      return book(variant, s, t);
    case Material::kCanvas:
      return canvas(variant, s, t);
    case Material::kMetal:
      return rgb(140, 142, 148) * grain(s, t, 0.01, 0.06F, 29);
    case Material::kLeaves:
      return rgb(50, 115, 40) * (0.6F + 0.6F * valueNoise(s, t, 0.03, 30));
    case Material::kLampShade:
      return rgb(230, 214, 174) * (0.95F + 0.05F * static_cast<float>(std::sin(2.0 * std::numbers::pi * s / 0.03)));
    case Material::kScreen:
      return rgb(16, 16, 18) * grain(s, t, 0.05, 0.1F, 31);
  }
  return rgb(255, 0, 255);  // unreachable for valid enumerators; loud magenta if memory was corrupted
}

}  // namespace vifusion::scene
