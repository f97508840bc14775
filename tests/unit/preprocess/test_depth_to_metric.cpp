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
