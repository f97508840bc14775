#include "vifusion/v4l2/z16.hpp"

#include <bit>
#include <cstddef>
#include <cstring>

namespace vifusion::v4l2 {
namespace {
constexpr int kZ16BytesPerPixel = 2;
constexpr int kBitsPerByte = 8;
}  // namespace

bool z16ToDepth(std::span<const std::uint8_t> frame, std::uint32_t bytes_per_line, ImageView<std::uint16_t> depth,
                ProblemText& problem) {
  if (depth.empty()) {
    problem.set("Z16: empty depth image (%dx%d)", depth.width, depth.height);
    return false;
  }
  const std::size_t row_bytes = static_cast<std::size_t>(depth.width) * kZ16BytesPerPixel;
  const std::size_t needed =
      static_cast<std::size_t>(bytes_per_line) * static_cast<std::size_t>(depth.height - 1) + row_bytes;
  if (bytes_per_line < row_bytes || frame.size() < needed) {
    problem.set("Z16: frame of %zu bytes with %u bytes per line is too short for %dx%d (needs %zu)", frame.size(),
                bytes_per_line, depth.width, depth.height, needed);
    return false;
  }
  for (int y = 0; y < depth.height; ++y) {
    const std::uint8_t* in = frame.data() + static_cast<std::size_t>(bytes_per_line) * static_cast<std::size_t>(y);
    std::uint16_t* out = depth.row(y);
    if constexpr (std::endian::native == std::endian::little) {
      std::memcpy(out, in, row_bytes);
    } else {
      for (int x = 0; x < depth.width; ++x) {
        out[x] =
            static_cast<std::uint16_t>(in[kZ16BytesPerPixel * x] | (in[kZ16BytesPerPixel * x + 1] << kBitsPerByte));
      }
    }
  }
  return true;
}

}  // namespace vifusion::v4l2
