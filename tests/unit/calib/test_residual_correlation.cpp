#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include "vifusion/calib/residual_correlation.hpp"

namespace vifusion::calib {
namespace {

constexpr int kSize = 256;

Image<float> whiteNoise(std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> normal(0.0F, 1.0F);
  Image<float> image(kSize, kSize);
  for (std::size_t i = 0; i < image.pixelCount(); ++i) image.data()[i] = normal(rng);
  return image;
}

/// Mean over k×k boxes: each pixel shares (k − |dx|)(k − |dy|) of its k² inputs with the pixel at (dx, dy).
Image<float> boxFiltered(const Image<float>& in, int k) {
  Image<float> out(in.width() - k + 1, in.height() - k + 1);
  for (int y = 0; y < out.height(); ++y) {
    for (int x = 0; x < out.width(); ++x) {
      float sum = 0.0F;
      for (int j = 0; j < k; ++j) {
        for (int i = 0; i < k; ++i) sum += in(x + i, y + j);
      }
      out(x, y) = sum / static_cast<float>(k);
    }
  }
  return out;
}

TEST(ResidualCorrelation, WhiteNoiseIsOneSamplePerPixel) {
  ResidualCorrelation correlation(4);
  for (std::uint32_t seed = 1; seed <= 4; ++seed) correlation.add(whiteNoise(seed).view());
  EXPECT_DOUBLE_EQ(correlation.correlation(0, 0), 1.0);
  for (int dx = -4; dx <= 4; ++dx) {
    for (int dy = -4; dy <= 4; ++dy) {
      if (dx != 0 || dy != 0) {
        EXPECT_NEAR(correlation.correlation(dx, dy), 0.0, 0.01) << dx << "," << dy;
      }
    }
  }
  EXPECT_NEAR(correlation.pixelsPerSample(), 1.0, 0.3);
  EXPECT_LT(correlation.correlationLength_px(), 0.7);  // ρ(1) ≈ 0: the crossing is at 1/(1 − 1/e) ≈ 0.63
  EXPECT_EQ(correlation.samples(), 4 * kSize * kSize);
}

TEST(ResidualCorrelation, ABoxFilterGivesItsAreaAndOverlapShares) {
  // 3×3 boxes: ρ(1, 0) = 6/9, ρ(2, 0) = 3/9, ρ(1, 1) = 4/9, Σ_h ρ(h) = 9 (the box's area), 1/e crossed at
  // 1 + (2/3 − 1/e)/(2/3 − 1/3) = 1.90 px.
  ResidualCorrelation correlation(4);
  for (std::uint32_t seed = 1; seed <= 4; ++seed) correlation.add(boxFiltered(whiteNoise(seed), 3).view());
  EXPECT_NEAR(correlation.correlation(1, 0), 6.0 / 9.0, 0.02);
  EXPECT_NEAR(correlation.correlation(0, -2), 3.0 / 9.0, 0.02);
  EXPECT_NEAR(correlation.correlation(1, 1), 4.0 / 9.0, 0.02);
  EXPECT_NEAR(correlation.correlation(-1, 1), 4.0 / 9.0, 0.02);
  EXPECT_NEAR(correlation.correlation(3, 0), 0.0, 0.02);
  EXPECT_NEAR(correlation.pixelsPerSample(), 9.0, 0.5);
  EXPECT_NEAR(correlation.correlationLength_px(), 1.90, 0.05);
}

TEST(ResidualCorrelation, PixelsWithoutResidualAreSkipped) {
  Image<float> image = whiteNoise(9);
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; x += 2) image(x, y) = std::numeric_limits<float>::quiet_NaN();
  }
  ResidualCorrelation correlation(2);
  correlation.add(image.view());
  EXPECT_EQ(correlation.samples(), kSize * kSize / 2);
  EXPECT_DOUBLE_EQ(correlation.correlation(1, 0), 0.0);  // no pair at an odd horizontal lag
  EXPECT_NEAR(correlation.correlation(2, 0), 0.0, 0.02);
}

TEST(ResidualCorrelation, RejectsAWindowOutOfRange) {
  EXPECT_THROW(ResidualCorrelation(0), std::invalid_argument);
  EXPECT_THROW(ResidualCorrelation(33), std::invalid_argument);
}

}  // namespace
}  // namespace vifusion::calib
