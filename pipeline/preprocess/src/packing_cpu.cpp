// Host packing of raw depth and RGB888 into the uint32 words the shaders read (packing.glsl).
// Built from shifts rather than memcpy so strided views and any host byte order give the same words.

#include <algorithm>
#include <stdexcept>
#include <string>

#include "vifusion/preprocess/packing.hpp"

namespace vifusion::preprocess {
namespace {

std::size_t pixelCount(int width, int height) {
  return static_cast<std::size_t>(std::max(width, 0)) * static_cast<std::size_t>(std::max(height, 0));
}

void requireWords(std::size_t have, std::size_t need, const char* function) {
  if (have < need) {
    throw std::invalid_argument(std::string(function) + ": " + std::to_string(have) + " words given, " +
                                std::to_string(need) + " needed");
  }
}

}  // namespace

std::size_t packedDepthWordCount(int width, int height) { return (pixelCount(width, height) + 1) / 2; }

std::size_t packedRgbWordCount(int width, int height) { return (3 * pixelCount(width, height) + 3) / 4; }

void packDepth(ImageView<const std::uint16_t> raw, std::span<std::uint32_t> words) {
  const std::size_t word_count = packedDepthWordCount(raw.width, raw.height);
  requireWords(words.size(), word_count, "packDepth");
  std::fill_n(words.begin(), word_count, 0u);  // the padding half of an odd-sized image's last word
  std::size_t i = 0;
  for (int y = 0; y < raw.height; ++y) {
    for (int x = 0; x < raw.width; ++x, ++i) {
      words[i / 2] |= static_cast<std::uint32_t>(raw(x, y)) << (16u * (i & 1u));
    }
  }
}

void packRgb(ImageView<const Rgb8> rgb, std::span<std::uint32_t> words) {
  const std::size_t word_count = packedRgbWordCount(rgb.width, rgb.height);
  requireWords(words.size(), word_count, "packRgb");
  std::fill_n(words.begin(), word_count, 0u);
  std::size_t k = 0;  // byte index
  const auto put = [&](std::uint8_t byte) {
    words[k / 4] |= static_cast<std::uint32_t>(byte) << (8u * (k & 3u));
    ++k;
  };
  for (int y = 0; y < rgb.height; ++y) {
    for (int x = 0; x < rgb.width; ++x) {
      const Rgb8 pixel = rgb(x, y);
      put(pixel.r);
      put(pixel.g);
      put(pixel.b);
    }
  }
}

}  // namespace vifusion::preprocess
