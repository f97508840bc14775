#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "synthetic_images.hpp"
#include "vifusion/preprocess/cpu_reference.hpp"

namespace vifusion::preprocess {
namespace {

using test::fillImage;

// Up to 169 float weights are summed: the weighted mean of equal values carries a few ULP of
// rounding, so "unchanged" means within a relative 4e-6.
constexpr float kRelTol = 4e-6f;

/// The filter switched on with ElasticFusion's 13 × 13 window (the pipeline's default is off).
BilateralDepthParams paramsFor(const Image<float>& image) {
  BilateralDepthParams params;
  params.width = image.width();
  params.height = image.height();
  params.radius_px = 6;
  return params;
}

TEST(BilateralDepth, OffByDefaultWithElasticFusionsSpaceSigmaAndRangeFollowingTheNoiseModel) {
  const BilateralDepthParams params;
  EXPECT_EQ(params.radius_px, 0);  // off: raw positions and wide-span normals track better (kernel_params.hpp)
  EXPECT_FLOAT_EQ(params.sigma_space_px, 4.5f);
  EXPECT_FLOAT_EQ(params.range_sigmas, 3.0f);
  EXPECT_FLOAT_EQ(params.noise_a_m, 0.0012f);
  EXPECT_FLOAT_EQ(params.noise_b_per_m, 0.0019f);
  EXPECT_FLOAT_EQ(params.noise_z0_m, 0.4f);
}

TEST(BilateralDepth, RangeSigmaGrowsWithDepth) {
  // A 20 mm step is smoothed at 3.5 m (σ_range = 3·(1.2 + 1.9·3.1²) mm ≈ 58 mm) and kept at 0.8 m
  // (σ_range ≈ 4.5 mm, the step is 4.4 σ): quantisation steps of far depth are filtered, near edges stay.
  for (const float base_m : {0.8f, 3.5f}) {
    Image<float> depth(24, 12);
    fillImage(depth, [&](int x, int) { return x < 12 ? base_m : base_m + 0.02f; });
    Image<float> out(24, 12);
    bilateralDepthCpu(depth.view(), paramsFor(depth), out.view());
    const float moved_m = out(11, 6) - depth(11, 6);  // beside the step, pulled towards the far side?
    if (base_m < 1.0f) {
      EXPECT_LT(moved_m, 1e-4f) << "near step must survive";
    } else {
      EXPECT_GT(moved_m, 4e-3f) << "far quantisation-size step must be smoothed";
    }
  }
}

TEST(BilateralDepth, ConstantImageIsUnchangedEverywhere) {
  Image<float> depth(20, 15, 1.7f);
  Image<float> out(20, 15);
  bilateralDepthCpu(depth.view(), paramsFor(depth), out.view());
  for (int y = 0; y < 15; ++y) {
    for (int x = 0; x < 20; ++x) EXPECT_NEAR(out(x, y), 1.7f, kRelTol * 1.7f) << x << "," << y;
  }
}

TEST(BilateralDepth, PerspectivePlaneIsUnchangedInTheInterior) {
  // Under perspective a plane's inverse depth is linear in (u, v). The filter averages inverse depth
  // with weights symmetric under (dx, dy) → (−dx, −dy) on such a plane, so the result is the centre
  // value wherever the whole window lies inside the image: no bias on slanted surfaces (averaging
  // depth itself would bend them, since depth is convex in (u, v), and bias the ICP).
  Image<float> depth(30, 28);
  const auto plane = [](int x, int y) {
    return 1.0f / (0.8f - 0.012f * static_cast<float>(x) + 0.006f * static_cast<float>(y));
  };
  fillImage(depth, plane);
  Image<float> out(30, 28);
  const BilateralDepthParams params = paramsFor(depth);
  bilateralDepthCpu(depth.view(), params, out.view());
  const int r = params.radius_px;
  for (int y = r; y < 28 - r; ++y) {
    for (int x = r; x < 30 - r; ++x) EXPECT_NEAR(out(x, y), depth(x, y), kRelTol * depth(x, y)) << x << "," << y;
  }
}

TEST(BilateralDepth, StepEdgeIsPreserved) {
  // A 0.5 m step at 1 m is ~80 σ_range: weights across it are far below float resolution.
  Image<float> depth(24, 12);
  fillImage(depth, [](int x, int) { return x < 12 ? 1.0f : 1.5f; });
  Image<float> out(24, 12);
  bilateralDepthCpu(depth.view(), paramsFor(depth), out.view());
  for (int y = 0; y < 12; ++y) {
    for (int x = 0; x < 24; ++x) EXPECT_NEAR(out(x, y), depth(x, y), kRelTol * depth(x, y)) << x << "," << y;
  }
}

TEST(BilateralDepth, InvalidPixelsStayInvalidAndDoNotPullNeighbours) {
  Image<float> depth(17, 13);
  fillImage(depth, [](int x, int y) { return (x + 2 * y) % 5 == 0 ? 0.0f : 2.0f; });
  Image<float> out(17, 13, -1.0f);
  bilateralDepthCpu(depth.view(), paramsFor(depth), out.view());
  for (int y = 0; y < 13; ++y) {
    for (int x = 0; x < 17; ++x) {
      if (depth(x, y) == 0.0f) {
        EXPECT_EQ(out(x, y), 0.0f) << x << "," << y;
      } else {
        EXPECT_NEAR(out(x, y), 2.0f, kRelTol * 2.0f) << x << "," << y;
      }
    }
  }
}

TEST(BilateralDepth, TwoValidPixelsGiveTheWeightedMean) {
  Image<float> depth(9, 3, 0.0f);
  depth(4, 1) = 1.0f;
  depth(5, 1) = 1.01f;
  Image<float> out(9, 3);
  const BilateralDepthParams params = paramsFor(depth);
  bilateralDepthCpu(depth.view(), params, out.view());

  // Weights use the difference as seen from the centre, z_c²·(1/d − 1/z_c); the mean is taken of
  // inverse depth.
  const double d0 = 1.0;
  const double d1 = static_cast<double>(1.01f);
  const auto weight = [](double centre, double other) {
    const double diff = centre * centre * (1.0 / other - 1.0 / centre);
    const double sigma_range = 3.0 * (0.0012 + 0.0019 * (centre - 0.4) * (centre - 0.4));
    return std::exp(-1.0 / (2.0 * 4.5 * 4.5) - diff * diff / (2.0 * sigma_range * sigma_range));
  };
  const double w0 = weight(d0, d1);
  const double w1 = weight(d1, d0);
  EXPECT_NEAR(out(4, 1), (1.0 + w0) / (1.0 / d0 + w0 / d1), 1e-6);
  EXPECT_NEAR(out(5, 1), (1.0 + w1) / (1.0 / d1 + w1 / d0), 1e-6);
  EXPECT_EQ(out(3, 1), 0.0f);
}

TEST(BilateralDepth, NeighboursBeyondTheRadiusAreIgnored) {
  Image<float> depth(15, 1, 0.0f);
  depth(0, 0) = 1.0f;
  depth(7, 0) = 1.02f;   // 7 px from x = 0: outside the radius-6 window
  depth(13, 0) = 1.03f;  // 6 px from x = 7: inside
  Image<float> out(15, 1);
  bilateralDepthCpu(depth.view(), paramsFor(depth), out.view());
  EXPECT_EQ(out(0, 0), 1.0f);
  EXPECT_GT(out(7, 0), 1.02f);
  EXPECT_LT(out(13, 0), 1.03f);
}

TEST(BilateralDepth, RadiusZeroIsTheIdentity) {
  Image<float> depth(6, 5);
  fillImage(depth, [](int x, int y) { return 0.5f + 0.37f * static_cast<float>((x * 7 + y * 3) % 5); });
  Image<float> out(6, 5);
  BilateralDepthParams params = paramsFor(depth);
  params.radius_px = 0;
  bilateralDepthCpu(depth.view(), params, out.view());
  for (int y = 0; y < 5; ++y) {
    // The mean is of inverse depth: 1/(1/z) returns z to within an ULP.
    for (int x = 0; x < 6; ++x) EXPECT_FLOAT_EQ(out(x, y), depth(x, y));
  }
}

TEST(BilateralDepth, RejectsInPlaceFiltering) {
  Image<float> depth(4, 4, 1.0f);
  EXPECT_THROW(bilateralDepthCpu(depth.view(), paramsFor(depth), depth.view()), std::invalid_argument);
}

}  // namespace
}  // namespace vifusion::preprocess
