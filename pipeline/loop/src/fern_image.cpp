#include "vifusion/loop/fern_image.hpp"

#include <cmath>
#include <string>

#include "vifusion/core/error.hpp"

namespace vifusion::loop {
namespace {

std::string sizeText(int width, int height) { return std::to_string(width) + "×" + std::to_string(height); }

}  // namespace

void downsampleForFerns(ImageView<const Rgb8> rgb, ImageView<const std::uint16_t> depth_raw, double depth_scale_m,
                        int factor, float max_depth_m, FernImage& out) {
  if (factor < 1) throw Error("fern downsampling: factor " + std::to_string(factor) + " must be ≥ 1");
  if (rgb.width != depth_raw.width || rgb.height != depth_raw.height) {
    throw Error("fern downsampling: colour " + sizeText(rgb.width, rgb.height) + " and depth " +
                sizeText(depth_raw.width, depth_raw.height) + " must be registered (same size)");
  }
  if (rgb.width <= 0 || rgb.height <= 0 || rgb.width % factor != 0 || rgb.height % factor != 0) {
    throw Error("fern downsampling: frame " + sizeText(rgb.width, rgb.height) +
                " must be non-empty and a multiple of the factor " + std::to_string(factor));
  }
  if (out.width() != rgb.width / factor || out.height() != rgb.height / factor) {
    throw Error("fern downsampling: output " + sizeText(out.width(), out.height()) + " must be " +
                sizeText(rgb.width / factor, rgb.height / factor) + " for a " + sizeText(rgb.width, rgb.height) +
                " frame and factor " + std::to_string(factor));
  }
  if (!(depth_scale_m > 0.0) || !std::isfinite(depth_scale_m)) {
    throw Error("fern downsampling: depth_scale_m " + std::to_string(depth_scale_m) + " must be finite and > 0");
  }

  // Largest valid raw value: raw·scale ≤ max_depth_m. Compared in raw units, so no per-pixel conversion.
  const double max_raw_d = std::floor(static_cast<double>(max_depth_m) / depth_scale_m);
  const std::uint32_t max_raw = max_raw_d >= 65535.0 ? 65535u : static_cast<std::uint32_t>(max_raw_d);
  const std::uint32_t block_pixels = static_cast<std::uint32_t>(factor * factor);

  for (int v = 0; v < out.height(); ++v) {
    for (int u = 0; u < out.width(); ++u) {
      std::uint32_t sum_r = 0, sum_g = 0, sum_b = 0;
      std::uint64_t sum_depth_raw = 0;
      std::uint32_t valid = 0;
      for (int y = v * factor; y < (v + 1) * factor; ++y) {
        const Rgb8* rgb_row = rgb.row(y);
        const std::uint16_t* depth_row = depth_raw.row(y);
        for (int x = u * factor; x < (u + 1) * factor; ++x) {
          sum_r += rgb_row[x].r;
          sum_g += rgb_row[x].g;
          sum_b += rgb_row[x].b;
          const std::uint32_t d = depth_row[x];
          if (d != 0 && d <= max_raw) {
            sum_depth_raw += d;
            ++valid;
          }
        }
      }
      const std::uint32_t half = block_pixels / 2;
      out.rgb(u, v) = Rgb8{static_cast<std::uint8_t>((sum_r + half) / block_pixels),
                           static_cast<std::uint8_t>((sum_g + half) / block_pixels),
                           static_cast<std::uint8_t>((sum_b + half) / block_pixels)};
      out.depth_m(u, v) =
          2 * valid >= block_pixels
              ? static_cast<float>(static_cast<double>(sum_depth_raw) * depth_scale_m / static_cast<double>(valid))
              : 0.0f;
    }
  }
}

void downsampleForFerns(const RgbdFrame& frame, int factor, float max_depth_m, FernImage& out) {
  downsampleForFerns(frame.rgb.view(), frame.depth.view(), frame.depth_scale_m, factor, max_depth_m, out);
}

}  // namespace vifusion::loop
