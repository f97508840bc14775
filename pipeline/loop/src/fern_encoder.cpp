#include "vifusion/loop/fern_encoder.hpp"

#include <algorithm>
#include <string>

#include "vifusion/core/error.hpp"

namespace vifusion::loop {

static_assert(kFernTests == 4, "encode() writes the R, G, B and depth bits");

std::uint64_t SplitMix64::next() {
  state_ += 0x9E3779B97F4A7C15ull;
  std::uint64_t z = state_;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

std::uint32_t SplitMix64::uniformBelow(std::uint32_t n) {
  return static_cast<std::uint32_t>(((next() >> 32) * static_cast<std::uint64_t>(n)) >> 32);
}

double SplitMix64::uniformUnit() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

void FernCodes::set(int fern, std::uint8_t code) {
  std::uint8_t& slot = codes_[static_cast<std::size_t>(fern)];
  const std::uint8_t stored = code < kFernCodeCount ? code : kInvalidFernCode;
  valid_count_ += (stored != kInvalidFernCode) - (slot != kInvalidFernCode);
  slot = stored;
}

double fernDissimilarity(const FernCodes& a, const FernCodes& b) {
  if (a.size() != b.size()) {
    throw Error("fern dissimilarity: codes of " + std::to_string(a.size()) + " and " + std::to_string(b.size()) +
                " ferns cannot be compared");
  }
  const int n = std::min(a.validCount(), b.validCount());
  if (n == 0) return 1.0;
  int co = 0;
  for (int f = 0; f < a.size(); ++f) co += a.isValid(f) && a.code(f) == b.code(f);
  return static_cast<double>(n - co) / static_cast<double>(n);
}

FernEncoder::FernEncoder(const FernOptions& options, int width, int height) : width_(width), height_(height) {
  options.validate();
  if (width < 1 || height < 1) {
    throw Error("fern encoder: downsampled size " + std::to_string(width) + "×" + std::to_string(height) +
                " must be at least 1×1");
  }
  SplitMix64 rng(options.seed);
  const double depth_range_m = static_cast<double>(options.max_depth_m) - static_cast<double>(options.min_depth_m);
  ferns_.resize(static_cast<std::size_t>(options.num_ferns));
  for (Fern& fern : ferns_) {
    fern.x = static_cast<int>(rng.uniformBelow(static_cast<std::uint32_t>(width)));
    fern.y = static_cast<int>(rng.uniformBelow(static_cast<std::uint32_t>(height)));
    fern.red = static_cast<std::uint8_t>(rng.uniformBelow(256));
    fern.green = static_cast<std::uint8_t>(rng.uniformBelow(256));
    fern.blue = static_cast<std::uint8_t>(rng.uniformBelow(256));
    fern.depth_m_threshold =
        static_cast<float>(static_cast<double>(options.min_depth_m) + rng.uniformUnit() * depth_range_m);
  }
}

void FernEncoder::encode(const FernImage& image, FernCodes& out) const {
  if (image.width() != width_ || image.height() != height_ || out.size() != numFerns()) {
    throw Error("fern encoder: image " + std::to_string(image.width()) + "×" + std::to_string(image.height()) +
                " with " + std::to_string(out.size()) + " codes, expected " + std::to_string(width_) + "×" +
                std::to_string(height_) + " with " + std::to_string(numFerns()));
  }
  for (int f = 0; f < numFerns(); ++f) {
    const Fern& fern = ferns_[static_cast<std::size_t>(f)];
    const float depth_m = image.depth_m(fern.x, fern.y);
    if (!(depth_m > 0.0f)) {
      out.set(f, kInvalidFernCode);
      continue;
    }
    const Rgb8 c = image.rgb(fern.x, fern.y);
    const int code = (c.r > fern.red ? 1 : 0) | (c.g > fern.green ? 2 : 0) | (c.b > fern.blue ? 4 : 0) |
                     (depth_m > fern.depth_m_threshold ? 8 : 0);
    out.set(f, static_cast<std::uint8_t>(code));
  }
}

}  // namespace vifusion::loop
