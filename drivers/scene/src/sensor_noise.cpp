#include "vifusion/scene/sensor_noise.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "vifusion/scene/counter_rng.hpp"

namespace vifusion::scene {
namespace {

// Random streams, one per use, so the draws of different steps never coincide.
constexpr std::uint64_t kJitterStream = 1;
constexpr std::uint64_t kDepthStream = 2;
constexpr std::uint64_t kColourStreamRg = 3;
constexpr std::uint64_t kColourStreamB = 4;
constexpr std::uint64_t kDotPatternSeed = 0x4b696e656374ULL;  // fixed projector pattern

constexpr int kCell_px = 3;                   // one projector dot per 3×3 cell
constexpr int kWindowRadius_px = 4;           // 9×9 window of the dot filter
constexpr double kInlierDistance_px = 0.1;    // disparity inlier threshold, after weighting
constexpr double kValidFraction = 1.0 / 1.2;  // fraction of dots that must be valid / inliers
constexpr int kFillRadiusSquared_px2 = 9;     // pixels a dot fills: r² ≤ 9

/// Per-pixel random counter: frame in the high half, pixel in the low half.
std::uint64_t pixelCounter(std::uint64_t frame_index, int x, int y, int width) {
  return (frame_index << 32) | static_cast<std::uint32_t>(y * width + x);
}

struct Offset {
  int dx = 0;
  int dy = 0;
};

/// Offsets with r² ≤ 9 sorted by (r², dy, dx): the first accepted dot in this order is the one
/// simkinect's sequential fill leaves in a pixel (largest fill weight 1/(1 + r²), ties to the dot
/// visited first in raster order).
constexpr std::array<Offset, 29> fillOrder() {
  std::array<Offset, 29> order{};
  std::size_t n = 0;
  for (int r2 = 0; r2 <= kFillRadiusSquared_px2; ++r2) {
    for (int dy = -3; dy <= 3; ++dy) {
      for (int dx = -3; dx <= 3; ++dx) {
        if (dx * dx + dy * dy == r2) order[n++] = {dx, dy};
      }
    }
  }
  return order;
}
constexpr std::array<Offset, 29> kFillOrder = fillOrder();

/// simkinect's window weights 1/(1.44·r²), 1 at the centre.
constexpr std::array<double, 81> windowWeights() {
  std::array<double, 81> w{};
  for (int dy = -kWindowRadius_px; dy <= kWindowRadius_px; ++dy) {
    for (int dx = -kWindowRadius_px; dx <= kWindowRadius_px; ++dx) {
      const int r2 = dx * dx + dy * dy;
      w[static_cast<std::size_t>((dy + kWindowRadius_px) * 9 + dx + kWindowRadius_px)] =
          r2 == 0 ? 1.0 : 1.0 / (1.44 * r2);
    }
  }
  return w;
}
constexpr std::array<double, 81> kWindowWeights = windowWeights();

/// Bilinear sample of depth at (x, y) inside the image; nearest neighbour if a tap has no depth.
double sampleDepth(const ImageView<const float>& depth_m, double x, double y) {
  const int x0 = std::min(static_cast<int>(x), depth_m.width - 2 < 0 ? 0 : depth_m.width - 2);
  const int y0 = std::min(static_cast<int>(y), depth_m.height - 2 < 0 ? 0 : depth_m.height - 2);
  const int x1 = std::min(x0 + 1, depth_m.width - 1);
  const int y1 = std::min(y0 + 1, depth_m.height - 1);
  const double fx = x - x0;
  const double fy = y - y0;
  const double d00 = depth_m(x0, y0);
  const double d10 = depth_m(x1, y0);
  const double d01 = depth_m(x0, y1);
  const double d11 = depth_m(x1, y1);
  if (d00 > 0.0 && d10 > 0.0 && d01 > 0.0 && d11 > 0.0) {
    return (1.0 - fy) * ((1.0 - fx) * d00 + fx * d10) + fy * ((1.0 - fx) * d01 + fx * d11);
  }
  return depth_m(fx < 0.5 ? x0 : x1, fy < 0.5 ? y0 : y1);
}

}  // namespace

CameraNoiseModel configuredNoiseModel(const SensorNoiseOptions& options, const Eigen::Vector3d& grey_weights,
                                      int subsampling) {
  constexpr double kUniformRoundingVariance = 1.0 / 12.0;  // of rounding to whole units
  constexpr double kDepthStep_m = 0.01;                    // step 4 rounds z to centimetres
  const double focal_baseline_px_m = options.focal_length_px * options.baseline_m;
  // Step 4's index is kKinectBandingConstant_cm / z_cm = (kKinectBandingConstant_cm / 100 m) / z.
  const double disparity_per_index_px = focal_baseline_px_m / (kKinectBandingConstant_cm / 100.0);
  const double index_variance = options.depth_noise_sigma * options.depth_noise_sigma + kUniformRoundingVariance;
  const double step_px = options.disparity_step_px;
  CameraNoiseModel model;
  model.depth.focal_baseline_px_m = focal_baseline_px_m;
  model.depth.disparity_sigma_px = std::sqrt(step_px * step_px * kUniformRoundingVariance +
                                             disparity_per_index_px * disparity_per_index_px * index_variance);
  model.depth.quantisation_m = kDepthStep_m;
  model.depth.lateral_sigma_px = options.jitter_sigma_px / subsampling;
  const double channel_variance = options.intensity_sigma * options.intensity_sigma + kUniformRoundingVariance;
  model.intensity.sigma = std::sqrt(grey_weights.squaredNorm() * channel_variance);
  return model;
}

SensorNoise::SensorNoise(const SensorNoiseOptions& options, RowPool& pool) : options_(options), pool_(pool) {
  if (!(options.focal_length_px > 0.0) || !(options.baseline_m > 0.0) || !(options.depth_scale > 0.0)) {
    throw std::invalid_argument("SensorNoise: focal_length_px, baseline_m and depth_scale must be > 0");
  }
  if (!(options.jitter_sigma_px >= 0.0) || !(options.disparity_step_px >= 0.0) || !(options.depth_noise_sigma >= 0.0) ||
      !(options.intensity_sigma >= 0.0)) {
    throw std::invalid_argument("SensorNoise: noise σ and disparity step must be >= 0");
  }
}

void SensorNoise::reserve(int width, int height) {
  if (disparity_px_.width() == width && disparity_px_.height() == height) return;
  disparity_px_.resize(width, height);
  accepted_.resize(width, height);
  dots_.resize(width, height);
  for (int cy = 0; cy * kCell_px < height; ++cy) {
    for (int cx = 0; cx * kCell_px < width; ++cx) {
      const std::uint64_t bits =
          counterBits(kDotPatternSeed, static_cast<std::uint64_t>(cy), static_cast<std::uint64_t>(cx));
      const int x = cx * kCell_px + static_cast<int>(bits % kCell_px);
      const int y = cy * kCell_px + static_cast<int>((bits >> 8) % kCell_px);
      if (x < width && y < height) dots_(x, y) = 1;
    }
  }
}

void SensorNoise::addDepthNoise(ImageView<const float> depth_m, ImageView<std::uint16_t> noisy_depth,
                                std::uint64_t frame_index) {
  addDepthNoise(depth_m, noisy_depth, frame_index, 1);
}

void SensorNoise::addDepthNoise(ImageView<const float> depth_m, ImageView<std::uint16_t> noisy_depth,
                                std::uint64_t frame_index, int subsampling) {
  if (subsampling < 1 || depth_m.width != noisy_depth.width * subsampling ||
      depth_m.height != noisy_depth.height * subsampling) {
    throw std::invalid_argument("SensorNoise: clean depth is " + std::to_string(depth_m.width) + "x" +
                                std::to_string(depth_m.height) + " but the output is " +
                                std::to_string(noisy_depth.width) + "x" + std::to_string(noisy_depth.height) +
                                " subsampled by " + std::to_string(subsampling));
  }
  if (depth_m.empty()) return;
  reserve(depth_m.width, depth_m.height);
  jitterAndQuantise(depth_m, frame_index);
  if (options_.dot_pattern) acceptDots();
  fillAndAddNoise(noisy_depth, subsampling, frame_index);
}

void SensorNoise::jitterAndQuantise(ImageView<const float> depth_m, std::uint64_t frame_index) {
  const double fb_px_m = options_.focal_length_px * options_.baseline_m;
  const double step = options_.disparity_step_px;
  const double max_x = depth_m.width - 1;
  const double max_y = depth_m.height - 1;
  ImageView<float> disparity = disparity_px_.view();
  pool_.forRows(depth_m.height, [&](int row_begin, int row_end) {
    for (int y = row_begin; y < row_end; ++y) {
      for (int x = 0; x < depth_m.width; ++x) {
        double z_m = depth_m(x, y);
        if (options_.jitter_sigma_px > 0.0) {
          const NormalPair shift =
              normalPair(options_.seed, kJitterStream, pixelCounter(frame_index, x, y, depth_m.width));
          const double sx = std::clamp(x + options_.jitter_sigma_px * shift.first, 0.0, max_x);
          const double sy = std::clamp(y + options_.jitter_sigma_px * shift.second, 0.0, max_y);
          z_m = sampleDepth(depth_m, sx, sy);
        }
        double d_px = z_m > 0.0 ? fb_px_m / z_m : 0.0;
        if (step > 0.0) d_px = std::nearbyint(d_px / step) * step;
        disparity(x, y) = static_cast<float>(d_px);
      }
    }
  });
}

void SensorNoise::acceptDots() {
  const ImageView<const float> disparity = disparity_px_.view();
  const ImageView<const std::uint8_t> dots = dots_.view();
  ImageView<std::uint8_t> accepted = accepted_.view();
  const int width = disparity.width;
  const int height = disparity.height;
  pool_.forRows(height, [&](int row_begin, int row_end) {
    for (int y = row_begin; y < row_end; ++y) {
      for (int x = 0; x < width; ++x) {
        accepted(x, y) = 0;
        const bool window_inside = x >= kWindowRadius_px && x < width - kWindowRadius_px && y >= kWindowRadius_px &&
                                   y < height - kWindowRadius_px;
        if (!window_inside || dots(x, y) == 0 || !(disparity(x, y) > 0.0F)) continue;
        int dot_count = 0;
        int valid_dots = 0;
        int valid_pixels = 0;
        double sum_px = 0.0;
        for (int dy = -kWindowRadius_px; dy <= kWindowRadius_px; ++dy) {
          for (int dx = -kWindowRadius_px; dx <= kWindowRadius_px; ++dx) {
            const float d = disparity(x + dx, y + dy);
            const bool valid = d > 0.0F;
            const bool dot = dots(x + dx, y + dy) != 0;
            dot_count += dot;
            valid_dots += dot && valid;
            valid_pixels += valid;
            if (valid) sum_px += d;
          }
        }
        if (valid_dots <= kValidFraction * dot_count) continue;
        const double mean_px = sum_px / valid_pixels;
        int inlier_dots = 0;
        for (int dy = -kWindowRadius_px; dy <= kWindowRadius_px; ++dy) {
          for (int dx = -kWindowRadius_px; dx <= kWindowRadius_px; ++dx) {
            const float d = disparity(x + dx, y + dy);
            if (dots(x + dx, y + dy) == 0 || !(d > 0.0F)) continue;
            const double weight =
                kWindowWeights[static_cast<std::size_t>((dy + kWindowRadius_px) * 9 + dx + kWindowRadius_px)];
            inlier_dots += std::abs(d - mean_px) * weight < kInlierDistance_px;
          }
        }
        if (inlier_dots > kValidFraction * dot_count) accepted(x, y) = 1;
      }
    }
  });
}

void SensorNoise::fillAndAddNoise(ImageView<std::uint16_t> noisy_depth, int subsampling,
                                  std::uint64_t frame_index) const {
  const ImageView<const float> disparity = disparity_px_.view();
  const ImageView<const std::uint8_t> accepted = accepted_.view();
  const double fb_px_m = options_.focal_length_px * options_.baseline_m;
  pool_.forRows(noisy_depth.height, [&](int row_begin, int row_end) {
    for (int out_y = row_begin; out_y < row_end; ++out_y) {
      for (int out_x = 0; out_x < noisy_depth.width; ++out_x) {
        // The sensor's pixel this output pixel keeps; its draws are the ones the full image gives it.
        const int x = out_x * subsampling;
        const int y = out_y * subsampling;
        double d_px = disparity(x, y);
        if (options_.dot_pattern) {
          d_px = 0.0;
          for (const Offset& o : kFillOrder) {
            if (accepted.contains(x + o.dx, y + o.dy) && accepted(x + o.dx, y + o.dy) != 0) {
              d_px = disparity(x + o.dx, y + o.dy);
              break;
            }
          }
        }
        noisy_depth(out_x, out_y) = 0;
        if (!(d_px > 0.0)) continue;
        const double z_cm = std::nearbyint(100.0 * fb_px_m / d_px);
        if (!(z_cm > 0.0)) continue;
        const double n = normal(options_.seed, kDepthStream, pixelCounter(frame_index, x, y, disparity.width));
        const double index = std::nearbyint(kKinectBandingConstant_cm / z_cm + options_.depth_noise_sigma * n + 0.5);
        if (!(index > 0.0)) continue;
        const double units = std::nearbyint(kKinectBandingConstant_cm / index / 100.0 * options_.depth_scale);
        if (units <= 65535.0) noisy_depth(out_x, out_y) = static_cast<std::uint16_t>(units);
      }
    }
  });
}

void SensorNoise::addIntensityNoise(ImageView<Rgb8> rgb, std::uint64_t frame_index) const {
  const double sigma = options_.intensity_sigma;
  if (!(sigma > 0.0) || rgb.empty()) return;
  const auto noisy = [sigma](std::uint8_t value, double n) {
    return static_cast<std::uint8_t>(std::clamp(std::nearbyint(value + sigma * n), 0.0, 255.0));
  };
  pool_.forRows(rgb.height, [&](int row_begin, int row_end) {
    for (int y = row_begin; y < row_end; ++y) {
      for (int x = 0; x < rgb.width; ++x) {
        const std::uint64_t counter = pixelCounter(frame_index, x, y, rgb.width);
        const NormalPair rg = normalPair(options_.seed, kColourStreamRg, counter);
        const double b = normal(options_.seed, kColourStreamB, counter);
        Rgb8& pixel = rgb(x, y);
        pixel = Rgb8{noisy(pixel.r, rg.first), noisy(pixel.g, rg.second), noisy(pixel.b, b)};
      }
    }
  });
}

}  // namespace vifusion::scene
