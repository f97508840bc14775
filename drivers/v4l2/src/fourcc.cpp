#include "vifusion/v4l2/fourcc.hpp"

namespace vifusion::v4l2 {

std::array<char, 5> fourccText(std::uint32_t fourcc) {
  constexpr int kBitsPerChar = 8;
  constexpr char kFirstPrintable = ' ';
  constexpr char kLastPrintable = '~';
  std::array<char, 5> text{};
  for (int i = 0; i < 4; ++i) {
    const char c = static_cast<char>((fourcc >> (kBitsPerChar * i)) & 0xFFu);
    text[static_cast<std::size_t>(i)] = (c >= kFirstPrintable && c <= kLastPrintable) ? c : '?';
  }
  return text;
}

int bytesPerPixel(std::uint32_t fourcc) {
  switch (fourcc) {
    case kFourccZ16:
    case kFourccYuyv:
      return 2;
    case kFourccGrey:
      return 1;
    default:
      return 0;
  }
}

}  // namespace vifusion::v4l2
