#pragma once
// V4L2 pixel format codes used by the ZR300/R200 camera and their memory layout.

#include <linux/videodev2.h>

#include <array>
#include <cstdint>

namespace vifusion::v4l2 {

/// A V4L2 fourcc from its four characters, first character in the lowest byte (v4l2_fourcc()).
constexpr std::uint32_t makeFourcc(char a, char b, char c, char d) {
  return static_cast<std::uint32_t>(static_cast<unsigned char>(a)) |
         static_cast<std::uint32_t>(static_cast<unsigned char>(b)) << 8 |
         static_cast<std::uint32_t>(static_cast<unsigned char>(c)) << 16 |
         static_cast<std::uint32_t>(static_cast<unsigned char>(d)) << 24;
}

/// 16-bit little-endian depth, one unit = the DS4 "depth units" XU value in µm. Mainline uvcvideo learned
/// this GUID only with the format patch (sensors.md §1.2), so an unpatched kernel grants another format.
inline constexpr std::uint32_t kFourccZ16 = V4L2_PIX_FMT_Z16;
/// Packed 4:2:2 Y0 U Y1 V, 2 bytes per pixel (the colour camera's "YUY2").
inline constexpr std::uint32_t kFourccYuyv = V4L2_PIX_FMT_YUYV;
/// 8-bit grey (left IR, or the ZR300 fisheye's RAW8).
inline constexpr std::uint32_t kFourccGrey = V4L2_PIX_FMT_GREY;
static_assert(kFourccZ16 == makeFourcc('Z', '1', '6', ' ') && kFourccYuyv == makeFourcc('Y', 'U', 'Y', 'V'));

/// The four characters, with non-printable bytes as '?': "Z16 ", "YUYV".
std::array<char, 5> fourccText(std::uint32_t fourcc);

/// Bytes per pixel of the packed formats above, 0 for a format this module does not lay out.
int bytesPerPixel(std::uint32_t fourcc);

}  // namespace vifusion::v4l2
