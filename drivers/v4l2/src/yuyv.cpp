#include "vifusion/v4l2/yuyv.hpp"

#include <cmath>
#include <cstddef>

namespace vifusion::v4l2 {
namespace {

constexpr int kYuyvBytesPerPixel = 2;
// 20 fractional bits: the largest sum, 239·1.16·2²⁰ + 127·2.02·2²⁰ ≈ 5.6·10⁸, stays well inside int32.
constexpr int kFractionBits = 20;
constexpr double kFixedOne = static_cast<double>(1 << kFractionBits);
constexpr std::int32_t kRoundingHalf = 1 << (kFractionBits - 1);

// BT.601 luma weights and the limited-range code spans.
constexpr double kKr = 0.299;
constexpr double kKb = 0.114;
constexpr double kKg = 1.0 - kKr - kKb;
constexpr double kLumaSpan = 219.0;    // Y codes 16 … 235
constexpr double kChromaSpan = 224.0;  // Cb, Cr codes 16 … 240
constexpr double kFullSpan = 255.0;
constexpr std::int32_t kLumaOffset = 16;
constexpr std::int32_t kChromaOffset = 128;
constexpr std::int32_t kLargestLevel = 255;

constexpr std::int32_t fixedPoint(double coefficient) {
  return static_cast<std::int32_t>(coefficient * kFixedOne + (coefficient >= 0 ? 0.5 : -0.5));
}

constexpr std::int32_t kYScale = fixedPoint(kFullSpan / kLumaSpan);
constexpr std::int32_t kRFromCr = fixedPoint(kFullSpan / kChromaSpan * 2.0 * (1.0 - kKr));
constexpr std::int32_t kGFromCb = fixedPoint(kFullSpan / kChromaSpan * 2.0 * (1.0 - kKb) * kKb / kKg);
constexpr std::int32_t kGFromCr = fixedPoint(kFullSpan / kChromaSpan * 2.0 * (1.0 - kKr) * kKr / kKg);
constexpr std::int32_t kBFromCb = fixedPoint(kFullSpan / kChromaSpan * 2.0 * (1.0 - kKb));

std::uint8_t toLevel(std::int32_t fixed) {
  const std::int32_t level = (fixed + kRoundingHalf) >> kFractionBits;  // arithmetic shift (C++20)
  return static_cast<std::uint8_t>(level < 0 ? 0 : (level > kLargestLevel ? kLargestLevel : level));
}

/// Shares the chroma terms between the two pixels of a pair.
struct ChromaTerms {
  std::int32_t r = 0;
  std::int32_t g = 0;
  std::int32_t b = 0;
};

ChromaTerms chromaTerms(std::uint8_t cb, std::uint8_t cr) {
  const std::int32_t u = static_cast<std::int32_t>(cb) - kChromaOffset;
  const std::int32_t v = static_cast<std::int32_t>(cr) - kChromaOffset;
  return {kRFromCr * v, -kGFromCb * u - kGFromCr * v, kBFromCb * u};
}

Rgb8 toRgb(std::uint8_t y, const ChromaTerms& chroma) {
  const std::int32_t luma = kYScale * (static_cast<std::int32_t>(y) - kLumaOffset);
  return {toLevel(luma + chroma.r), toLevel(luma + chroma.g), toLevel(luma + chroma.b)};
}

}  // namespace

Rgb8 bt601LimitedToRgb(std::uint8_t y, std::uint8_t cb, std::uint8_t cr) { return toRgb(y, chromaTerms(cb, cr)); }

bool yuyvToRgb(std::span<const std::uint8_t> frame, std::uint32_t bytes_per_line, ImageView<Rgb8> rgb,
               ProblemText& problem) {
  if (rgb.empty() || rgb.width % 2 != 0) {
    problem.set("YUYV: image width %d must be even and positive (height %d)", rgb.width, rgb.height);
    return false;
  }
  const std::size_t row_bytes = static_cast<std::size_t>(rgb.width) * kYuyvBytesPerPixel;
  const std::size_t needed =
      static_cast<std::size_t>(bytes_per_line) * static_cast<std::size_t>(rgb.height - 1) + row_bytes;
  if (bytes_per_line < row_bytes || frame.size() < needed) {
    problem.set("YUYV: frame of %zu bytes with %u bytes per line is too short for %dx%d (needs %zu)", frame.size(),
                bytes_per_line, rgb.width, rgb.height, needed);
    return false;
  }
  for (int y = 0; y < rgb.height; ++y) {
    const std::uint8_t* in = frame.data() + static_cast<std::size_t>(bytes_per_line) * static_cast<std::size_t>(y);
    Rgb8* out = rgb.row(y);
    for (int x = 0; x < rgb.width; x += 2, in += 2 * kYuyvBytesPerPixel) {
      // Y0 Cb Y1 Cr
      const ChromaTerms chroma = chromaTerms(in[1], in[3]);
      out[x] = toRgb(in[0], chroma);
      out[x + 1] = toRgb(in[2], chroma);
    }
  }
  return true;
}

}  // namespace vifusion::v4l2
