// libFuzzer target: the image decoding paths of the dataset readers (image_files.hpp) on arbitrary bytes:
// a 16-bit depth PNG file, a colour PNG/JPEG file, and a compressed colour image held in memory (.klg). The
// first byte chooses the path, the next two the expected width and height (1…64 px, as small seeds keep the
// fuzzer fast); the rest is the image. Decoding is OpenCV's (libpng, libjpeg): what is fuzzed is that every
// failure, wrong size or wrong type becomes an Error naming the file, and that an accepted image has exactly
// the expected size.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "fuzz_support.hpp"
#include "image_files.hpp"

namespace {

using namespace vifusion;
using namespace vifusion::fuzz;

enum class Path : std::uint8_t { kDepthPng, kColorFile, kColorInMemory, kCount };
constexpr int kMaxSide = 64;  ///< [px]
constexpr std::size_t kHeaderBytes = 3;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const ScratchFolder folder;
  static datasets::detail::ImageDecoder decoder;
  static Image<std::uint16_t> depth;
  static Image<Rgb8> rgb;
  if (size < kHeaderBytes) return 0;
  const int width = 1 + data[1] % kMaxSide;
  const int height = 1 + data[2] % kMaxSide;
  const std::span<const std::uint8_t> image(data + kHeaderBytes, size - kHeaderBytes);
  switch (static_cast<Path>(data[0] % static_cast<std::uint8_t>(Path::kCount))) {
    case Path::kDepthPng:
      folder.write("depth.png", image);
      if (parsedOrNamedError({"depth.png"},
                             [&] { decoder.readDepthPng(folder.path(), "depth.png", width, height, depth); })) {
        require(depth.width() == width && depth.height() == height);
      }
      break;
    case Path::kColorFile:
      folder.write("color.png", image);
      if (parsedOrNamedError({"color.png"},
                             [&] { decoder.readColor(folder.path(), "color.png", width, height, rgb); })) {
        require(rgb.width() == width && rgb.height() == height);
      }
      break;
    case Path::kColorInMemory:
      if (parsedOrNamedError({"frame 0 image"},
                             [&] { decoder.decodeRgbOrder(image, "frame 0 image", width, height, rgb); })) {
        require(rgb.width() == width && rgb.height() == height);
      }
      break;
    case Path::kCount:
      break;
  }
  return 0;
}
