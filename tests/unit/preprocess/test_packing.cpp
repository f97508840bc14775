#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "synthetic_images.hpp"
#include "vifusion/preprocess/packing.hpp"

namespace vifusion::preprocess {
namespace {

using test::fillImage;

TEST(Packing, WordCountsRoundUp) {
  EXPECT_EQ(packedDepthWordCount(640, 480), 640u * 480u / 2u);
  EXPECT_EQ(packedDepthWordCount(5, 3), 8u);  // 15 pixels
  EXPECT_EQ(packedRgbWordCount(640, 480), 640u * 480u * 3u / 4u);
  EXPECT_EQ(packedRgbWordCount(5, 3), 12u);  // 45 bytes
  EXPECT_EQ(packedRgbWordCount(1, 1), 1u);
}

TEST(Packing, DepthRoundTripThroughTheShaderUnpacking) {
  Image<std::uint16_t> raw(5, 3);  // odd pixel count: rows straddle words
  fillImage(raw, [](int x, int y) { return static_cast<std::uint16_t>(0xF000 + 257 * x + 4099 * y); });
  std::vector<std::uint32_t> words(packedDepthWordCount(5, 3), 0xDEADBEEFu);
  packDepth(raw.view(), words);
  for (int y = 0; y < 3; ++y) {
    for (int x = 0; x < 5; ++x) {
      const std::size_t i = static_cast<std::size_t>(y * 5 + x);
      EXPECT_EQ(depthOfWord(words[i / 2], i), raw(x, y)) << x << "," << y;
    }
  }
  EXPECT_EQ(words.back() >> 16, 0u) << "padding half-word must be zero";
}

TEST(Packing, DepthFromAStridedView) {
  std::vector<std::uint16_t> storage = {1, 2, 99, 3, 4, 99};  // 2 × 2 image, stride 3
  const ImageView<const std::uint16_t> raw(storage.data(), 2, 2, 3);
  std::vector<std::uint32_t> words(packedDepthWordCount(2, 2));
  packDepth(raw, words);
  EXPECT_EQ(words[0], 1u | (2u << 16));
  EXPECT_EQ(words[1], 3u | (4u << 16));
}

TEST(Packing, RgbRoundTripThroughTheShaderUnpacking) {
  Image<Rgb8> rgb(5, 3);
  fillImage(rgb, [](int x, int y) {
    return Rgb8{static_cast<std::uint8_t>(10 * x + y), static_cast<std::uint8_t>(200 - x), static_cast<std::uint8_t>(37 * y + 1)};
  });
  std::vector<std::uint32_t> words(packedRgbWordCount(5, 3), 0xDEADBEEFu);
  packRgb(rgb.view(), words);
  for (int y = 0; y < 3; ++y) {
    for (int x = 0; x < 5; ++x) {
      const std::size_t k = 3 * static_cast<std::size_t>(y * 5 + x);
      EXPECT_EQ(byteOfWord(words[k / 4], k), rgb(x, y).r);
      EXPECT_EQ(byteOfWord(words[(k + 1) / 4], k + 1), rgb(x, y).g);
      EXPECT_EQ(byteOfWord(words[(k + 2) / 4], k + 2), rgb(x, y).b);
    }
  }
  EXPECT_EQ(words.back() >> 8, 0u) << "45 bytes: the last word's three padding bytes must be zero";
}

TEST(Packing, LittleEndianHostPacksToTheImageBytes) {
  if constexpr (std::endian::native != std::endian::little) GTEST_SKIP() << "big-endian host";
  Image<Rgb8> rgb(4, 2);
  fillImage(rgb, [](int x, int y) { return Rgb8{static_cast<std::uint8_t>(x), static_cast<std::uint8_t>(y), 77}; });
  std::vector<std::uint32_t> words(packedRgbWordCount(4, 2));
  packRgb(rgb.view(), words);
  EXPECT_EQ(std::memcmp(words.data(), rgb.data(), 4 * 2 * 3), 0);

  Image<std::uint16_t> raw(4, 2);
  fillImage(raw, [](int x, int y) { return static_cast<std::uint16_t>(1000 * y + x); });
  std::vector<std::uint32_t> depth_words(packedDepthWordCount(4, 2));
  packDepth(raw.view(), depth_words);
  EXPECT_EQ(std::memcmp(depth_words.data(), raw.data(), 4 * 2 * sizeof(std::uint16_t)), 0);
}

TEST(Packing, RejectsTooFewWords) {
  Image<std::uint16_t> raw(4, 4);
  std::vector<std::uint32_t> words(7);
  EXPECT_THROW(packDepth(raw.view(), words), std::invalid_argument);
  Image<Rgb8> rgb(4, 4);
  std::vector<std::uint32_t> rgb_words(11);
  EXPECT_THROW(packRgb(rgb.view(), rgb_words), std::invalid_argument);
}

}  // namespace
}  // namespace vifusion::preprocess
