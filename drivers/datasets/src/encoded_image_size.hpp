#pragma once
// The pixel size a PNG or JPEG file declares in its header, read without decoding it. The dataset readers
// compare it with the size they expect before OpenCV allocates anything: a corrupt or hostile header could
// otherwise make a few kB of compressed zeros expand into gigabytes (OpenCV accepts up to 2^30 pixels).

#include <cstdint>
#include <optional>
#include <span>

namespace vifusion::datasets::detail {

struct EncodedImageSize {
  std::uint32_t width = 0;   ///< [px]
  std::uint32_t height = 0;  ///< [px]
};

/// The size in a PNG's IHDR chunk or a JPEG's first start-of-frame segment; nullopt for bytes that are
/// neither, or whose header is cut short.
std::optional<EncodedImageSize> encodedImageSize(std::span<const std::uint8_t> bytes);

}  // namespace vifusion::datasets::detail
