#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <vector>

#include "vifusion/preprocess/cpu_reference.hpp"

namespace vifusion::preprocess {
namespace {

TEST(DepthToMetric, DefaultsAreMillimetreSensorWithElasticFusionGate) {
  const DepthToMetricParams params;
  EXPECT_FLOAT_EQ(params.depth_scale_m, 0.001f);
  EXPECT_FLOAT_EQ(params.min_depth_m, 0.3f);
  EXPECT_FLOAT_EQ(params.max_depth_m, 4.0f);
}

TEST(DepthToMetric, GateBoundsAreInclusive) {
  // 0.25 m per unit keeps every product exact, so the bounds are hit exactly.
  Image<std::uint16_t> raw(7, 1);
  const std::uint16_t values[7] = {0, 3, 4, 6, 8, 9, 65535};
  for (int x = 0; x < 7; ++x) raw(x, 0) = values[x];
  DepthToMetricParams params{.width = 7, .height = 1, .depth_scale_m = 0.25f, .min_depth_m = 1.0f, .max_depth_m = 2.0f};
  Image<float> depth(7, 1, -1.0f);
  depthToMetricCpu(raw.view(), params, depth.view());
  const float expected[7] = {0.0f, 0.0f, 1.0f, 1.5f, 2.0f, 0.0f, 0.0f};
  for (int x = 0; x < 7; ++x) EXPECT_EQ(depth(x, 0), expected[x]) << "x=" << x;
}

TEST(DepthToMetric, MillimetreDefaults) {
  const std::uint16_t values[8] = {0, 299, 300, 1000, 1234, 4000, 4001, 65535};
  Image<std::uint16_t> raw(8, 1);
  for (int x = 0; x < 8; ++x) raw(x, 0) = values[x];
  DepthToMetricParams params;
  params.width = 8;
  params.height = 1;
  Image<float> depth(8, 1, -1.0f);
  depthToMetricCpu(raw.view(), params, depth.view());
  EXPECT_EQ(depth(0, 0), 0.0f);
  EXPECT_EQ(depth(1, 0), 0.0f);
  EXPECT_NEAR(depth(2, 0), 0.3f, 1e-6f);  // 300 mm is kept
  EXPECT_NEAR(depth(3, 0), 1.0f, 1e-6f);
  EXPECT_NEAR(depth(4, 0), 1.234f, 1e-6f);
  EXPECT_NEAR(depth(5, 0), 4.0f, 1e-6f);  // 4000 mm is kept
  EXPECT_EQ(depth(6, 0), 0.0f);
  EXPECT_EQ(depth(7, 0), 0.0f);
}

TEST(DepthToMetric, TumScaleFiveThousandPerMetre) {
  Image<std::uint16_t> raw(2, 1);
  raw(0, 0) = 5000;
  raw(1, 0) = 12500;
  DepthToMetricParams params{.width = 2, .height = 1, .depth_scale_m = 1.0f / 5000.0f};
  Image<float> depth(2, 1);
  depthToMetricCpu(raw.view(), params, depth.view());
  EXPECT_NEAR(depth(0, 0), 1.0f, 1e-6f);
  EXPECT_NEAR(depth(1, 0), 2.5f, 1e-6f);
}

TEST(DepthToMetric, RemovesTheInverseDepthBiasBeforeTheGate) {
  // 1/z = 1/z_raw − b with the simulated Kinect's b: z_raw 2 m is 2.0057 m, 3.99 m is 4.0127 m and
  // falls out of the 4 m gate, 0.3 m stays 0.3001 m. A bias ≥ 1/z_raw (no finite depth) is invalid.
  constexpr float kBias_per_m = 1.4232849e-3f;
  const std::uint16_t values[4] = {10000, 19950, 1500, 0};
  Image<std::uint16_t> raw(4, 1);
  for (int x = 0; x < 4; ++x) raw(x, 0) = values[x];
  DepthToMetricParams params{.width = 4, .height = 1, .depth_scale_m = 1.0f / 5000.0f,
                             .inverse_depth_bias_per_m = kBias_per_m};
  Image<float> depth(4, 1, -1.0f);
  depthToMetricCpu(raw.view(), params, depth.view());
  for (int x = 0; x < 3; ++x) {
    const double z_raw_m = values[x] / 5000.0;
    const double expected_m = 1.0 / (1.0 / z_raw_m - kBias_per_m);
    if (x == 1) {
      EXPECT_GT(expected_m, 4.0);
      EXPECT_EQ(depth(x, 0), 0.0f);
    } else {
      EXPECT_NEAR(depth(x, 0), expected_m, 1e-6 * expected_m) << "x=" << x;
    }
  }
  EXPECT_NEAR(depth(0, 0), 2.0057, 1e-4);
  EXPECT_EQ(depth(3, 0), 0.0f);

  params.inverse_depth_bias_per_m = 0.5f;  // 1/z_raw = 0.5 at 2 m: the corrected depth is infinite
  params.max_depth_m = 1e9f;
  depthToMetricCpu(raw.view(), params, depth.view());
  EXPECT_EQ(depth(0, 0), 0.0f);
  EXPECT_EQ(depth(1, 0), 0.0f);
  EXPECT_NEAR(depth(2, 0), 0.3 / (1.0 - 0.15), 1e-6);
}

TEST(DepthToMetric, StridedOutputLeavesPaddingAlone) {
  Image<std::uint16_t> raw(3, 2, 1500);
  std::vector<float> storage(5 * 2, -7.0f);
  const ImageView<float> depth(storage.data(), 3, 2, 5);
  DepthToMetricParams params{.width = 3, .height = 2};
  depthToMetricCpu(raw.view(), params, depth);
  for (int y = 0; y < 2; ++y) {
    for (int x = 0; x < 5; ++x) {
      if (x < 3) {
        EXPECT_NEAR(storage[y * 5 + x], 1.5f, 1e-6f);
      } else {
        EXPECT_EQ(storage[y * 5 + x], -7.0f);
      }
    }
  }
}

TEST(DepthToMetric, RejectsViewsThatDisagreeWithParams) {
  Image<std::uint16_t> raw(4, 4);
  Image<float> depth(4, 3);
  DepthToMetricParams params{.width = 4, .height = 4};
  EXPECT_THROW(depthToMetricCpu(raw.view(), params, depth.view()), std::invalid_argument);
}

}  // namespace
}  // namespace vifusion::preprocess
