#include <gtest/gtest.h>

#include <stdexcept>

#include "vifusion/preprocess/cpu_reference.hpp"

namespace vifusion::preprocess {
namespace {

TEST(RgbToIntensity, DefaultsAreRec601Luma) {
  const RgbToIntensityParams params;
  EXPECT_FLOAT_EQ(params.weight_r, 0.299f);
  EXPECT_FLOAT_EQ(params.weight_g, 0.587f);
  EXPECT_FLOAT_EQ(params.weight_b, 0.114f);
}

TEST(RgbToIntensity, KnownColours) {
  const Rgb8 colours[6] = {{0, 0, 0}, {255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {255, 255, 255}, {10, 100, 200}};
  const double expected[6] = {0.0,
                              0.299 * 255,
                              0.587 * 255,
                              0.114 * 255,
                              255.0,
                              0.299 * 10 + 0.587 * 100 + 0.114 * 200};
  Image<Rgb8> rgb(3, 2);
  for (int i = 0; i < 6; ++i) rgb(i % 3, i / 3) = colours[i];
  Image<float> intensity(3, 2);
  RgbToIntensityParams params;
  params.width = 3;
  params.height = 2;
  rgbToIntensityCpu(rgb.view(), params, intensity.view());
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(intensity(i % 3, i / 3), expected[i], 1e-4) << "colour " << i;
}

TEST(RgbToIntensity, WeightsApplyToBytesInOrderSoBgrSwapsThem) {
  Image<Rgb8> bgr(1, 1, Rgb8{200, 100, 10});  // memory order B, G, R
  Image<float> intensity(1, 1);
  const RgbToIntensityParams params{.width = 1, .height = 1, .weight_r = 0.114f, .weight_g = 0.587f, .weight_b = 0.299f};
  rgbToIntensityCpu(bgr.view(), params, intensity.view());
  EXPECT_NEAR(intensity(0, 0), 0.299 * 10 + 0.587 * 100 + 0.114 * 200, 1e-4);
}

TEST(RgbToIntensity, RejectsViewsThatDisagreeWithParams) {
  Image<Rgb8> rgb(4, 4);
  Image<float> intensity(4, 4);
  const RgbToIntensityParams params{.width = 4, .height = 5};
  EXPECT_THROW(rgbToIntensityCpu(rgb.view(), params, intensity.view()), std::invalid_argument);
}

}  // namespace
}  // namespace vifusion::preprocess
