#include "encoded_image_size.hpp"

#include <algorithm>
#include <array>
#include <cstddef>

namespace vifusion::datasets::detail {
namespace {

// PNG (ISO/IEC 15948 §5.2, §11.2.2): the 8-byte signature, then the IHDR chunk: length (4), type "IHDR" (4),
// width (4), height (4), all big-endian.
constexpr std::array<std::uint8_t, 8> kPngSignature = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
constexpr std::size_t kPngIhdrTypeOffset = 12;
constexpr std::size_t kPngWidthOffset = 16;
constexpr std::size_t kPngHeaderBytes = 24;

// JPEG (ITU-T T.81 §B.1.1): 0xFF 0xD8 (SOI), then segments 0xFF <marker> <length: 2 bytes, big-endian, itself
// included>. A start-of-frame segment (SOF0…SOF15 but DHT 0xC4, JPG 0xC8, DAC 0xCC) holds precision (1),
// height (2), width (2) after its length.
constexpr std::uint8_t kJpegMarkerPrefix = 0xFF;
constexpr std::uint8_t kJpegSoi = 0xD8;
constexpr std::uint8_t kJpegSos = 0xDA;  ///< start of scan: no frame header after it
constexpr std::uint8_t kJpegFirstSof = 0xC0, kJpegLastSof = 0xCF;
constexpr std::uint8_t kJpegDht = 0xC4, kJpegJpg = 0xC8, kJpegDac = 0xCC;
constexpr std::uint8_t kJpegFirstRst = 0xD0, kJpegLastRst = 0xD7, kJpegTem = 0x01;  ///< markers with no length
constexpr std::size_t kJpegSofHeightOffset = 5;  ///< from the marker's 0xFF: FF, marker, length (2), precision
constexpr std::size_t kJpegSofBytes = 9;

std::uint32_t bigEndian32(const std::uint8_t* p) {
  return std::uint32_t{p[0]} << 24 | std::uint32_t{p[1]} << 16 | std::uint32_t{p[2]} << 8 | p[3];
}
std::uint32_t bigEndian16(const std::uint8_t* p) { return std::uint32_t{p[0]} << 8 | p[1]; }

bool isStartOfFrame(std::uint8_t marker) {
  return marker >= kJpegFirstSof && marker <= kJpegLastSof && marker != kJpegDht && marker != kJpegJpg &&
         marker != kJpegDac;
}

std::optional<EncodedImageSize> pngSize(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < kPngHeaderBytes) return std::nullopt;
  const std::uint8_t* type = bytes.data() + kPngIhdrTypeOffset;
  if (type[0] != 'I' || type[1] != 'H' || type[2] != 'D' || type[3] != 'R') return std::nullopt;
  return EncodedImageSize{bigEndian32(bytes.data() + kPngWidthOffset), bigEndian32(bytes.data() + kPngWidthOffset + 4)};
}

std::optional<EncodedImageSize> jpegSize(std::span<const std::uint8_t> bytes) {
  std::size_t at = 2;  // after SOI
  while (at + 2 <= bytes.size()) {
    if (bytes[at] != kJpegMarkerPrefix) return std::nullopt;
    const std::uint8_t marker = bytes[at + 1];
    if (marker == kJpegMarkerPrefix) {  // fill byte before a marker
      ++at;
      continue;
    }
    if (marker == kJpegSos) return std::nullopt;
    if ((marker >= kJpegFirstRst && marker <= kJpegLastRst) || marker == kJpegTem) {
      at += 2;
      continue;
    }
    if (at + 4 > bytes.size()) return std::nullopt;
    const std::uint32_t length = bigEndian16(bytes.data() + at + 2);
    if (length < 2) return std::nullopt;
    if (isStartOfFrame(marker)) {
      if (at + kJpegSofBytes > bytes.size() || length + 2 < kJpegSofBytes) return std::nullopt;
      const std::uint8_t* height = bytes.data() + at + kJpegSofHeightOffset;
      return EncodedImageSize{bigEndian16(height + 2), bigEndian16(height)};
    }
    at += 2 + length;
  }
  return std::nullopt;
}

}  // namespace

std::optional<EncodedImageSize> encodedImageSize(std::span<const std::uint8_t> bytes) {
  if (bytes.size() >= kPngSignature.size() && std::equal(kPngSignature.begin(), kPngSignature.end(), bytes.begin())) {
    return pngSize(bytes);
  }
  if (bytes.size() >= 2 && bytes[0] == kJpegMarkerPrefix && bytes[1] == kJpegSoi) return jpegSize(bytes);
  return std::nullopt;
}

}  // namespace vifusion::datasets::detail
