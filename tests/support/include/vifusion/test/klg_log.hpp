#pragma once
// .klg log bytes as ElasticFusion's loggers write them, for the reader's tests and the fuzz seeds: int32 frame
// count, then per frame int64 t [µs], int32 depth and image sizes, the depth bytes, the image bytes (all
// little-endian, as KlgReader reads them).

#include <cstdint>
#include <cstring>
#include <vector>

namespace vifusion::test {

struct KlgFrame {
  std::int64_t t_us = 0;
  std::vector<std::uint8_t> depth;  ///< raw 640×480×2 bytes, or zlib-compressed
  std::vector<std::uint8_t> image;  ///< raw 640×480×3 bytes, JPEG, or empty
};

template <typename T>
void appendLittleEndian(std::vector<std::uint8_t>& bytes, T value) {
  const std::size_t at = bytes.size();
  bytes.resize(at + sizeof(T));  // resize + memcpy: GCC 12 misreads insert() of a small array here
  std::memcpy(bytes.data() + at, &value, sizeof(T));
}

/// The log of `frames`, whose header claims `frame_count` frames (the frames' number, or a corrupt count).
inline std::vector<std::uint8_t> klgBytes(const std::vector<KlgFrame>& frames, std::int32_t frame_count) {
  std::vector<std::uint8_t> bytes;
  appendLittleEndian(bytes, frame_count);
  for (const KlgFrame& frame : frames) {
    appendLittleEndian(bytes, frame.t_us);
    appendLittleEndian(bytes, static_cast<std::int32_t>(frame.depth.size()));
    appendLittleEndian(bytes, static_cast<std::int32_t>(frame.image.size()));
    bytes.insert(bytes.end(), frame.depth.begin(), frame.depth.end());
    bytes.insert(bytes.end(), frame.image.begin(), frame.image.end());
  }
  return bytes;
}

}  // namespace vifusion::test
