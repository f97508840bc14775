#pragma once
// FNV-1a, 32 bits (http://www.isthe.com/chongo/tech/comp/fnv/): a checksum of image bytes that the C++
// tests and tests/node/read_recording.mjs compute alike, so that two images compare as two numbers.

#include <cstdint>
#include <span>

#include "vifusion/core/image.hpp"
#include "vifusion/core/sensor_data.hpp"

namespace vifusion::test {

inline constexpr std::uint32_t kFnv1aOffsetBasis = 2166136261u;
inline constexpr std::uint32_t kFnv1aPrime = 16777619u;

inline std::uint32_t fnv1aUpdate(std::uint32_t hash, std::span<const std::uint8_t> bytes) {
  for (const std::uint8_t byte : bytes) hash = (hash ^ byte) * kFnv1aPrime;
  return hash;
}

/// Depth as the recording's 16UC1 image holds it: row by row, each pixel little-endian (low byte first).
inline std::uint32_t fnv1aOfDepth(const Image<std::uint16_t>& depth) {
  std::uint32_t hash = kFnv1aOffsetBasis;
  for (int y = 0; y < depth.height(); ++y) {
    for (int x = 0; x < depth.width(); ++x) {
      const std::uint16_t value = depth(x, y);
      const std::uint8_t bytes[2] = {static_cast<std::uint8_t>(value & 0xffu), static_cast<std::uint8_t>(value >> 8)};
      hash = fnv1aUpdate(hash, bytes);
    }
  }
  return hash;
}

/// Colour as rgb8: row by row, bytes R, G, B.
inline std::uint32_t fnv1aOfRgb(const Image<Rgb8>& rgb) {
  std::uint32_t hash = kFnv1aOffsetBasis;
  for (int y = 0; y < rgb.height(); ++y) {
    for (int x = 0; x < rgb.width(); ++x) {
      const Rgb8 pixel = rgb(x, y);
      const std::uint8_t bytes[3] = {pixel.r, pixel.g, pixel.b};
      hash = fnv1aUpdate(hash, bytes);
    }
  }
  return hash;
}

}  // namespace vifusion::test
