#pragma once
// Synthetic RGB-D views for place-recognition tests: a background and boxes of random colour and depth at
// random places, and a "same view again" copy with an exposure shift and sensor noise. Integer draws only
// (std::mt19937's output is specified by the standard), so the frames are the same on every machine.

#include <algorithm>
#include <cstdint>
#include <random>

#include "vifusion/core/sensor_data.hpp"

namespace vifusion::test {

/// A scene of `boxes` boxes on a background, depth in mm (scale 0.001), all depths within 0.45–4.35 m.
inline RgbdFrame makeBoxScene(std::uint32_t seed, int width, int height, int boxes = 40) {
  std::mt19937 rng(seed);
  const auto byte = [&rng] { return static_cast<std::uint8_t>(rng() % 256); };
  RgbdFrame frame;
  frame.depth_scale_m = 0.001;
  frame.rgb.resize(width, height, Rgb8{byte(), byte(), byte()});
  frame.depth.resize(width, height, static_cast<std::uint16_t>(1000 + rng() % 2900));
  for (int box = 0; box < boxes; ++box) {
    const int x0 = static_cast<int>(rng() % static_cast<std::uint32_t>(width));
    const int y0 = static_cast<int>(rng() % static_cast<std::uint32_t>(height));
    const int w = 32 + static_cast<int>(rng() % 160);  // [px]
    const int h = 32 + static_cast<int>(rng() % 160);
    const Rgb8 colour{byte(), byte(), byte()};
    const auto depth_mm = static_cast<std::uint16_t>(450 + rng() % 3500);
    for (int y = y0; y < std::min(height, y0 + h); ++y) {
      for (int x = x0; x < std::min(width, x0 + w); ++x) {
        frame.rgb(x, y) = colour;
        frame.depth(x, y) = depth_mm;
      }
    }
  }
  return frame;
}

/// The same view with a global colour shift `shift` (exposure), ±8 colour noise per channel and ±1 % depth noise.
inline RgbdFrame noisyCopy(const RgbdFrame& frame, int shift, std::uint32_t seed) {
  std::mt19937 rng(seed);
  const auto clampByte = [](int v) { return static_cast<std::uint8_t>(std::clamp(v, 0, 255)); };
  RgbdFrame out = frame;
  for (int y = 0; y < frame.rgb.height(); ++y) {
    for (int x = 0; x < frame.rgb.width(); ++x) {
      const Rgb8 c = frame.rgb(x, y);
      out.rgb(x, y) = Rgb8{clampByte(c.r + shift + static_cast<int>(rng() % 17) - 8),
                           clampByte(c.g + shift + static_cast<int>(rng() % 17) - 8),
                           clampByte(c.b + shift + static_cast<int>(rng() % 17) - 8)};
      const int d = frame.depth(x, y);
      const int noise = d / 100;  // 1 %
      out.depth(x, y) =
          static_cast<std::uint16_t>(d + static_cast<int>(rng() % static_cast<std::uint32_t>(2 * noise + 1)) - noise);
    }
  }
  return out;
}

}  // namespace vifusion::test
