#pragma once
// Host side of the byte-format packing the shaders unpack (shaders/include/preprocess/packing.glsl):
// raw uint16 depth two pixels per uint32 word, RGB888 four bytes per word, both by linear
// (row-major) index and little-endian within a word. On a little-endian host that is the image's
// memory as is; these functions also handle strided views and do not depend on host byte order.

#include <cstddef>
#include <cstdint>
#include <span>

#include "vifusion/core/image.hpp"
#include "vifusion/preprocess/pixel_types.hpp"

namespace vifusion::preprocess {

/// Words holding a width × height uint16 image (two pixels per word, last word zero-padded).
std::size_t packedDepthWordCount(int width, int height);

/// Words holding a width × height RGB888 image (3 bytes per pixel, last word zero-padded).
std::size_t packedRgbWordCount(int width, int height);

/// Packs `raw` into `words` (size ≥ packedDepthWordCount); throws std::invalid_argument if too small.
void packDepth(ImageView<const std::uint16_t> raw, std::span<std::uint32_t> words);

/// Packs `rgb` into `words` (size ≥ packedRgbWordCount); throws std::invalid_argument if too small.
void packRgb(ImageView<const Rgb8> rgb, std::span<std::uint32_t> words);

/// The GLSL depthOfWord: raw depth of linear pixel `pixel_index`, given word pixel_index / 2.
constexpr std::uint32_t depthOfWord(std::uint32_t word, std::size_t pixel_index) {
  return (word >> (16u * (pixel_index & 1u))) & 0xFFFFu;
}

/// The GLSL byteOfWord: byte `byte_index` of the packed image, given word byte_index / 4.
constexpr std::uint32_t byteOfWord(std::uint32_t word, std::size_t byte_index) {
  return (word >> (8u * (byte_index & 3u))) & 0xFFu;
}

}  // namespace vifusion::preprocess
