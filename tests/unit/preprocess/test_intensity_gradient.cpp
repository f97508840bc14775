#include <gtest/gtest.h>

#include <stdexcept>

#include "synthetic_images.hpp"
#include "vifusion/preprocess/cpu_reference.hpp"

namespace vifusion::preprocess {
namespace {

TEST(IntensityGradient, LinearRampGivesItsSlopeInsideAndHalfOfItAtTheBorder) {
  // Border replicate makes the one-sided difference span one pixel instead of two.
  constexpr int kW = 9;
  constexpr int kH = 7;
  Image<float> intensity(kW, kH);
  test::fillImage(intensity, [](int x, int y) { return 3.0f * static_cast<float>(x) - 2.0f * static_cast<float>(y) + 100.0f; });
  Image<GradientPixel> gradient(kW, kH, GradientPixel::Zero());
  intensityGradientCpu(intensity.view(), {.width = kW, .height = kH}, gradient.view());
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      const float expected_u = (x == 0 || x == kW - 1) ? 1.5f : 3.0f;
      const float expected_v = (y == 0 || y == kH - 1) ? -1.0f : -2.0f;
      EXPECT_EQ(gradient(x, y), GradientPixel(expected_u, expected_v)) << x << "," << y;
    }
  }
}

TEST(IntensityGradient, ConstantImageHasZeroGradient) {
  Image<float> intensity(5, 4, 42.0f);
  Image<GradientPixel> gradient(5, 4, GradientPixel::Constant(-1.0f));
  intensityGradientCpu(intensity.view(), {.width = 5, .height = 4}, gradient.view());
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 5; ++x) EXPECT_EQ(gradient(x, y), GradientPixel::Zero());
  }
}

TEST(IntensityGradient, ImpulseResponseIsTheSobelKernelOverEight) {
  Image<float> intensity(5, 5, 0.0f);
  intensity(2, 2) = 8.0f;
  Image<GradientPixel> gradient(5, 5, GradientPixel::Zero());
  intensityGradientCpu(intensity.view(), {.width = 5, .height = 5}, gradient.view());
  EXPECT_EQ(gradient(1, 2), GradientPixel(2.0f, 0.0f));   // impulse on the right, centre row: weight 2
  EXPECT_EQ(gradient(3, 2), GradientPixel(-2.0f, 0.0f));
  EXPECT_EQ(gradient(2, 1), GradientPixel(0.0f, 2.0f));
  EXPECT_EQ(gradient(2, 3), GradientPixel(0.0f, -2.0f));
  EXPECT_EQ(gradient(1, 1), GradientPixel(1.0f, 1.0f));   // diagonal: weight 1 in both
  EXPECT_EQ(gradient(3, 3), GradientPixel(-1.0f, -1.0f));
  EXPECT_EQ(gradient(2, 2), GradientPixel::Zero());
  EXPECT_EQ(gradient(0, 0), GradientPixel::Zero());
}

TEST(IntensityGradient, RejectsViewsThatDisagreeWithParams) {
  Image<float> intensity(5, 4);
  Image<GradientPixel> gradient(4, 4, GradientPixel::Zero());
  EXPECT_THROW(intensityGradientCpu(intensity.view(), {.width = 5, .height = 4}, gradient.view()), std::invalid_argument);
}

}  // namespace
}  // namespace vifusion::preprocess
