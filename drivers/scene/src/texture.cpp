#include "vifusion/scene/texture.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include "texture_filter.hpp"
#include "vifusion/scene/counter_rng.hpp"

namespace vifusion::scene {
namespace {

using texture_filter::interval;
using texture_filter::NoiseLattice;
using texture_filter::oddCells;
using texture_filter::pulseTrain;
using texture_filter::sinMean;
using texture_filter::TextureFilter;
using texture_filter::valueNoise;
using texture_filter::wrap;

constexpr double kInfinity = std::numeric_limits<double>::infinity();

Albedo rgb(int r, int g, int b) {
  return Albedo(static_cast<float>(r), static_cast<float>(g), static_cast<float>(b)) / 255.0F;
}

/// Mean of a two-valued pattern that takes b on the fraction c of the footprint and a elsewhere
/// (exactly a at c = 0 and b at c = 1, so point samples keep their values).
template <class T>
T blend(const T& a, const T& b, float c) {
  return a * (1.0F - c) + b * c;
}

/// Fraction covered by either of two independent patterns with coverages a and b.
float either(float a, float b) { return 1.0F - (1.0F - a) * (1.0F - b); }

/// Multiplicative modulation 1 + amplitude·(2n − 1) from value noise n, averaged over the footprint.
float grain(double s_m, double t_m, double scale_m, float amplitude, std::uint32_t layer, const TextureFilter& f) {
  return 1.0F + amplitude * (2.0F * valueNoise(s_m, t_m, scale_m, layer, f.sWidth(), f.tWidth()) - 1.0F);
}

/// Deterministic palette pick: hash of (variant, salt) in [0, 1).
float pick(std::uint32_t variant, std::uint32_t salt) {
  return static_cast<float>(counterBits(variant, salt, 0x5eedu) >> 40) * 0x1.0p-24F;
}

Albedo wallStripes(double s, double t, const TextureFilter& f) {
  // Coarse: 45 cm stripes in two tones with a thin dark pinstripe at each border.
  Albedo base = blend(rgb(140, 168, 148), rgb(204, 189, 148), oddCells(s, 0.45, f.sWidth()));
  base *= blend(1.0F, 0.6F, pulseTrain(s, 0.45, 0.0, 0.012, f.sWidth()));
  // Medium: 9 cm checks of slightly different lightness (the XOR of two stripe patterns).
  const float odd_s = oddCells(s, 0.09, f.sWidth());
  const float odd_t = oddCells(t, 0.09, f.tWidth());
  base *= blend(1.0F, 0.9F, odd_s + odd_t - 2.0F * odd_s * odd_t);
  // Fine: paper grain.
  return base * grain(s, t, 0.012, 0.08F, 1, f);
}

Albedo wallPanels(double s, double t, const TextureFilter& f) {
  constexpr double kRailLow_m = 0.9;
  constexpr double kRailHigh_m = 0.96;
  const float wainscot = interval(t, -kInfinity, kRailLow_m, f.tWidth());
  const float rail = interval(t, kRailLow_m, kRailHigh_m, f.tWidth());
  const float plaster = interval(t, kRailHigh_m, kInfinity, f.tWidth());
  Albedo colour = Albedo::Zero();
  if (wainscot > 0.0F) {
    // Wainscot: 55 cm panels framed by 6 cm stiles with 1.5 cm grooves at the panel edges.
    const float stile =
        either(pulseTrain(s, 0.55, 0.0, 0.06, f.sWidth()),
               interval(t, -kInfinity, 0.08, f.tWidth()) + interval(t, kRailLow_m - 0.06, kInfinity, f.tWidth()));
    Albedo base = blend(rgb(199, 184, 158), rgb(168, 148, 122), stile);
    const float groove = either(pulseTrain(s, 0.55, 0.06, 0.075, f.sWidth()), interval(t, 0.08, 0.095, f.tWidth()));
    base *= blend(1.0F, 0.7F, groove);
    colour += wainscot * (base * grain(s, t, 0.015, 0.06F, 2, f));
  }
  if (rail > 0.0F) colour += rail * (rgb(120, 90, 62) * grain(s, t, 0.02, 0.1F, 3, f));
  if (plaster > 0.0F) {
    // Plaster: coarse blotches, medium mottling, fine stipple.
    const float coarse = grain(s, t, 0.6, 0.12F, 4, f);
    const float medium = grain(s, t, 0.12, 0.12F, 5, f);
    const float fine = grain(s, t, 0.012, 0.07F, 6, f);
    colour += plaster * (rgb(148, 163, 184) * coarse * medium * fine);
  }
  return colour;
}

Albedo wallBricks(double s, double t, const TextureFilter& f) {
  constexpr double kCourse_m = 0.085;
  constexpr double kBrick_m = 0.25;
  constexpr double kMortar_m = 0.012;
  // The course and brick of the sample decide the tone and the joint offset for the whole footprint:
  // where the footprint reaches a neighbouring brick it is mostly on the joint in between.
  const auto row = static_cast<std::int64_t>(std::floor(t / kCourse_m));
  const double shifted = s + ((row & 1) != 0 ? 0.5 * kBrick_m : 0.0);
  const auto column = static_cast<std::int64_t>(std::floor(shifted / kBrick_m));
  const float mortar = either(pulseTrain(shifted, kBrick_m, 0.0, kMortar_m, f.sWidth()),
                              pulseTrain(t, kCourse_m, 0.0, kMortar_m, f.tWidth()));
  Albedo colour = Albedo::Zero();
  if (mortar > 0.0F) colour += mortar * (rgb(190, 186, 178) * grain(s, t, 0.01, 0.06F, 7, f));
  if (mortar < 1.0F) {
    const float tone = 0.8F + 0.35F * NoiseLattice(8)(row, column);
    colour +=
        (1.0F - mortar) * (rgb(158, 84, 61) * tone * grain(s, t, 0.7, 0.1F, 9, f) * grain(s, t, 0.015, 0.08F, 10, f));
  }
  return colour;
}

Albedo floorPlanks(double s, double t, const TextureFilter& f) {
  constexpr double kWidth_m = 0.16;
  constexpr double kLength_m = 1.25;
  constexpr double kGap_m = 0.004;
  const auto row = static_cast<std::int64_t>(std::floor(t / kWidth_m));
  const double along = s + 1.37 * NoiseLattice(11)(row, 0);  // staggered joints
  const auto plank = static_cast<std::int64_t>(std::floor(along / kLength_m));
  const float gap =
      either(pulseTrain(t, kWidth_m, 0.0, kGap_m, f.tWidth()), pulseTrain(along, kLength_m, 0.0, kGap_m, f.sWidth()));
  Albedo colour = Albedo::Zero();
  if (gap > 0.0F) colour += gap * rgb(60, 40, 25);
  if (gap < 1.0F) {
    const float tone = 0.75F + 0.4F * NoiseLattice(12)(row, plank);
    // Grain: lines along the board, wavering with low-frequency noise. The waver is smooth over a
    // pixel, so only the lines' own 1.8 cm period is averaged.
    constexpr double kLinePeriod_m = 0.018;
    const double phase = t / kLinePeriod_m + 1.5 * valueNoise(along, t, 0.35, 13);
    const float lines =
        0.9F + 0.1F * sinMean(2.0 * std::numbers::pi * phase, f.width(0.0, 2.0 * std::numbers::pi / kLinePeriod_m));
    colour += (1.0F - gap) * (rgb(140, 97, 56) * tone * lines * grain(along, t, 0.01, 0.05F, 14, f));
  }
  return colour;
}

Albedo ceiling(double s, double t, const TextureFilter& f) {
  constexpr double kTile_m = 0.6;
  constexpr double kLine_m = 0.015;
  const float line =
      either(pulseTrain(s, kTile_m, 0.0, kLine_m, f.sWidth()), pulseTrain(t, kTile_m, 0.0, kLine_m, f.tWidth()));
  Albedo colour = Albedo::Zero();
  if (line > 0.0F) colour += line * rgb(170, 170, 165);
  if (line < 1.0F) {
    colour += (1.0F - line) * (rgb(220, 217, 209) * grain(s, t, 0.1, 0.05F, 15, f) * grain(s, t, 0.015, 0.06F, 16, f));
  }
  return colour;
}

Albedo rug(double s, double t, const TextureFilter& f) {
  // Diamonds |ds| + |dt| < 6 cm in 20 cm cells: a level set of ds + dt, whose gradient is (±1, ±1).
  const double ds = wrap(s, 0.2) - 0.1;
  const double dt = wrap(t, 0.2) - 0.1;
  const double diamond_width = f.width(ds < 0.0 ? -1.0 : 1.0, dt < 0.0 ? -1.0 : 1.0);
  const float diamond = interval(std::abs(ds) + std::abs(dt), -kInfinity, 0.06, diamond_width);
  Albedo base = blend(rgb(128, 36, 40), rgb(196, 160, 90), diamond);
  base =
      base.cwiseProduct(blend<Albedo>(Albedo::Ones(), rgb(150, 170, 235), oddCells(s, 0.6, f.sWidth())));  // navy bands
  return base * grain(s, t, 0.01, 0.1F, 17, f);
}

Albedo fabric(std::uint32_t variant, double s, double t, const TextureFilter& f) {
  const Albedo base =
      Albedo(0.25F + 0.5F * pick(variant, 1), 0.2F + 0.4F * pick(variant, 2), 0.2F + 0.5F * pick(variant, 3));
  const float band_s = pulseTrain(s, 0.14, 0.0, 0.035, f.sWidth());
  const float band_t = pulseTrain(t, 0.14, 0.0, 0.035, f.tWidth());
  Albedo colour = base;
  colour *= blend(1.0F, 0.72F, either(band_s, band_t));
  colour *= blend(1.0F, 0.8F, band_s * band_t);
  const float thread =
      either(pulseTrain(s, 0.14, 0.076, 0.084, f.sWidth()), pulseTrain(t, 0.14, 0.076, 0.084, f.tWidth()));
  colour = blend(colour, rgb(225, 215, 160), thread);
  return colour * grain(s, t, 0.4, 0.06F, 18, f) * grain(s, t, 0.008, 0.08F, 19, f);
}

Albedo wood(std::uint32_t variant, double s, double t, const TextureFilter& f) {
  static const Albedo kTones[] = {rgb(158, 115, 72), rgb(107, 72, 46), rgb(190, 158, 115)};
  const Albedo& tone = kTones[variant % 3];
  constexpr double kLinePeriod_m = 0.025;
  const double phase = t / kLinePeriod_m + 2.0 * valueNoise(s, t, 0.3, 20 + variant);
  const float lines =
      0.88F + 0.12F * sinMean(2.0 * std::numbers::pi * phase, f.width(0.0, 2.0 * std::numbers::pi / kLinePeriod_m));
  return tone * lines * grain(s, t, 0.01, 0.05F, 23, f);
}

Albedo paintedWood(std::uint32_t variant, double s, double t, const TextureFilter& f) {
  static const Albedo kPaints[] = {rgb(222, 216, 200), rgb(86, 120, 140), rgb(176, 98, 64), rgb(110, 130, 90)};
  Albedo paint = kPaints[variant % 4];
  const float groove = either(pulseTrain(s, 0.3, 0.0, 0.01, f.sWidth()), pulseTrain(t, 0.45, 0.0, 0.01, f.tWidth()));
  paint *= blend(1.0F, 0.65F, groove);  // panel grooves
  return paint * grain(s, t, 0.08, 0.05F, 24, f) * grain(s, t, 0.012, 0.04F, 25, f);
}

Albedo book(std::uint32_t variant, double s, double t, const TextureFilter& f) {
  Albedo cover(0.15F + 0.7F * pick(variant, 4), 0.1F + 0.6F * pick(variant, 5), 0.1F + 0.6F * pick(variant, 6));
  cover = blend(cover, rgb(214, 180, 90), pulseTrain(t, 0.12, 0.02, 0.035, f.tWidth()));  // title bands
  return cover * grain(s, t, 0.01, 0.05F, 26, f);
}

Albedo canvas(std::uint32_t variant, double s, double t, const TextureFilter& f) {
  // Low-frequency interference pattern (the composition) plus medium brush strokes. The waves'
  // periods are at least 0.5 m, tens of pixels anywhere in the room, so they are not averaged.
  const double a = 4.0 + 8.0 * pick(variant, 7);
  const double b = 4.0 + 8.0 * pick(variant, 8);
  const double phase = 6.3 * pick(variant, 9);
  const auto wave = [&](double fs, double ft, double offset) {
    return static_cast<float>(0.5 + 0.5 * std::sin(fs * s + ft * t + phase + offset));
  };
  const Albedo colour(0.15F + 0.75F * wave(a, 0.5 * b, 0.0), 0.15F + 0.7F * wave(-0.7 * a, b, 2.0),
                      0.15F + 0.7F * wave(0.4 * a, -0.9 * b, 4.0));
  return colour * grain(s, t, 0.03, 0.12F, 27, f) * grain(s, t, 0.01, 0.05F, 28, f);
}

}  // namespace

Albedo albedo(Material material, std::uint32_t variant, const Eigen::Vector2d& st_m, const Eigen::Matrix2d& J_st_px) {
  const double s = st_m.x();
  const double t = st_m.y();
  const TextureFilter f(J_st_px);
  switch (material) {
    case Material::kWallStripes:
      return wallStripes(s, t, f);
    case Material::kWallPanels:
      return wallPanels(s, t, f);
    case Material::kWallBricks:
      return wallBricks(s, t, f);
    case Material::kWhiteWall:
      return rgb(235, 235, 235);
    case Material::kFloorPlanks:
      return floorPlanks(s, t, f);
    case Material::kCeiling:
      return ceiling(s, t, f);
    case Material::kRug:
      return rug(s, t, f);
    case Material::kFabric:
      return fabric(variant, s, t, f);
    case Material::kWood:
      return wood(variant, s, t, f);
    case Material::kPaintedWood:
      return paintedWood(variant, s, t, f);
    case Material::kBook:
      return book(variant, s, t, f);
    case Material::kCanvas:
      return canvas(variant, s, t, f);
    case Material::kMetal:
      return rgb(140, 142, 148) * grain(s, t, 0.01, 0.06F, 29, f);
    case Material::kLeaves:
      return rgb(50, 115, 40) * (0.6F + 0.6F * valueNoise(s, t, 0.03, 30, f.sWidth(), f.tWidth()));
    case Material::kLampShade:
      return rgb(230, 214, 174) *
             (0.95F + 0.05F * sinMean(2.0 * std::numbers::pi * s / 0.03, f.width(2.0 * std::numbers::pi / 0.03, 0.0)));
    case Material::kScreen:
      return rgb(16, 16, 18) * grain(s, t, 0.05, 0.1F, 31, f);
  }
  return rgb(255, 0, 255);  // unreachable for valid enumerators; loud magenta if memory was corrupted
}

}  // namespace vifusion::scene
