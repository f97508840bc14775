#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "synthetic_images.hpp"
#include "vifusion/preprocess/cpu_reference.hpp"

namespace vifusion::preprocess {
namespace {

constexpr int kWidth = 64;
constexpr int kHeight = 48;

VertexMapParams testIntrinsics(float f_px, float fy_sign) {
  return {.width = kWidth, .height = kHeight, .fx = f_px, .fy = fy_sign * f_px, .cx = 31.5f, .cy = 23.5f};
}

NormalMapParams normalParams(int span_px = 1) {
  NormalMapParams params;
  params.width = kWidth;
  params.height = kHeight;
  params.span_px = span_px;
  return params;
}

bool inInterior(int x, int y, int span_px) {
  return x >= span_px && y >= span_px && x + span_px < kWidth && y + span_px < kHeight;
}

/// Depth of the plane {p : n·p = n·p0} along each pixel's ray, computed in double.
Image<float> planeDepth(const Eigen::Vector3d& n, const Eigen::Vector3d& p0, const VertexMapParams& k) {
  Image<float> depth(k.width, k.height);
  test::fillImage(depth, [&](int u, int v) {
    const Eigen::Vector3d ray((u - static_cast<double>(k.cx)) / k.fx, (v - static_cast<double>(k.cy)) / k.fy, 1.0);
    return static_cast<float>(n.dot(p0) / n.dot(ray));
  });
  return depth;
}

Image<NormalPixel> normalsOf(const Image<float>& depth, const VertexMapParams& intrinsics, int span_px = 1) {
  Image<VertexPixel> vertices(kWidth, kHeight, VertexPixel::Zero());
  vertexMapCpu(depth.view(), intrinsics, vertices.view());
  Image<NormalPixel> normals(kWidth, kHeight, NormalPixel::Constant(-9.0f));
  normalMapCpu(vertices.view(), normalParams(span_px), normals.view());
  return normals;
}

TEST(NormalMap, TiltedPlaneGivesTheAnalyticNormalForEitherSignOfFyAndAnySpan) {
  const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.4, -1.0).normalized();  // faces the camera: n·p < 0
  const Eigen::Vector3d p0(0.0, 0.0, 2.0);
  for (const int span : {1, 3}) {
    for (const float fy_sign : {1.0f, -1.0f}) {
      // f = 52.5 px keeps neighbouring vertices ~4 cm apart, so float rounding of the vertices
      // perturbs the differences by only ~1e-5 relative.
      const VertexMapParams intrinsics = testIntrinsics(52.5f, fy_sign);
      const Image<NormalPixel> normals = normalsOf(planeDepth(n, p0, intrinsics), intrinsics, span);
      for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kWidth; ++x) {
          if (!inInterior(x, y, span)) continue;
          const NormalPixel& normal = normals(x, y);
          SCOPED_TRACE("span " + std::to_string(span) + " fy sign " + std::to_string(fy_sign) + " at " +
                       std::to_string(x) + "," + std::to_string(y));
          ASSERT_EQ(normal.w(), 1.0f);
          EXPECT_NEAR(normal.x(), n.x(), 1e-4);
          EXPECT_NEAR(normal.y(), n.y(), 1e-4);
          EXPECT_NEAR(normal.z(), n.z(), 1e-4);
          EXPECT_NEAR(normal.head<3>().norm(), 1.0f, 1e-6f);
        }
      }
    }
  }
}

TEST(NormalMap, RealisticFocalLengthStillGivesTheAnalyticNormal) {
  // f = 525 px: neighbours ~4 mm apart at 2 m, float vertices limit the accuracy to ~1e-4.
  const Eigen::Vector3d n = Eigen::Vector3d(-0.2, 0.5, -1.0).normalized();
  const VertexMapParams intrinsics = testIntrinsics(525.0f, 1.0f);
  const Image<NormalPixel> normals = normalsOf(planeDepth(n, Eigen::Vector3d(0.1, 0.0, 2.0), intrinsics), intrinsics);
  for (int y = 1; y + 1 < kHeight; ++y) {
    for (int x = 1; x + 1 < kWidth; ++x) {
      ASSERT_EQ(normals(x, y).w(), 1.0f);
      EXPECT_LT((normals(x, y).head<3>().cast<double>() - n).norm(), 1e-3) << x << "," << y;
    }
  }
}

TEST(NormalMap, FrontoParallelPlaneFacesTheCamera) {
  // With fy > 0 the raw cross product points away from the camera (+z) and must be flipped; with
  // fy < 0 it already points towards it. Both must come out as (0, 0, −1).
  for (const float fy_sign : {1.0f, -1.0f}) {
    const VertexMapParams intrinsics = testIntrinsics(52.5f, fy_sign);
    const Image<NormalPixel> normals = normalsOf(Image<float>(kWidth, kHeight, 1.2f), intrinsics);
    for (int y = 1; y + 1 < kHeight; ++y) {
      for (int x = 1; x + 1 < kWidth; ++x) {
        EXPECT_EQ(normals(x, y), NormalPixel(0.0f, 0.0f, -1.0f, 1.0f)) << "fy sign " << fy_sign << " at " << x << "," << y;
      }
    }
  }
}

TEST(NormalMap, BorderOfSpanWidthIsInvalidAndTheInteriorValid) {
  const VertexMapParams intrinsics = testIntrinsics(52.5f, 1.0f);
  for (const int span : {1, 2, 4}) {
    const Image<NormalPixel> normals = normalsOf(Image<float>(kWidth, kHeight, 1.0f), intrinsics, span);
    for (int y = 0; y < kHeight; ++y) {
      for (int x = 0; x < kWidth; ++x) {
        EXPECT_EQ(normals(x, y).w(), inInterior(x, y, span) ? 1.0f : 0.0f) << "span " << span << " at " << x << "," << y;
      }
    }
  }
}

TEST(NormalMap, AHoleInvalidatesItsPixelAndThePixelsThatDifferenceAcrossIt) {
  for (const int span : {1, 2}) {
    Image<float> depth(kWidth, kHeight, 1.0f);
    depth(10, 10) = 0.0f;
    const Image<NormalPixel> normals = normalsOf(depth, testIntrinsics(52.5f, 1.0f), span);
    EXPECT_EQ(normals(10, 10), NormalPixel::Zero());
    EXPECT_EQ(normals(10 - span, 10), NormalPixel::Zero());  // right neighbour missing
    EXPECT_EQ(normals(10 + span, 10), NormalPixel::Zero());  // left neighbour missing
    EXPECT_EQ(normals(10, 10 - span), NormalPixel::Zero());  // lower neighbour missing
    EXPECT_EQ(normals(10, 10 + span), NormalPixel::Zero());  // upper neighbour missing
    EXPECT_EQ(normals(9, 9).w(), 1.0f);
    EXPECT_EQ(normals(10 + span + 1, 10).w(), 1.0f);
  }
}

TEST(NormalMap, WiderSpanAveragesQuantisationPlateaus) {
  // A slanted plane at 2 m seen at f = 525 px, its depth quantised into 1 cm plateaus a few pixels
  // wide (structured-light banding): one-pixel differences see flat plateaus and steps, a 4-pixel
  // span sees the slope.
  const Eigen::Vector3d n = Eigen::Vector3d(0.6, 0.0, -1.0).normalized();
  const VertexMapParams intrinsics = testIntrinsics(525.0f, 1.0f);
  Image<float> depth = planeDepth(n, Eigen::Vector3d(0.0, 0.0, 2.0), intrinsics);
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) depth(x, y) = 0.01f * std::round(depth(x, y) / 0.01f);
  }
  const auto medianAngle = [&](int span) {
    std::vector<double> angles;
    const Image<NormalPixel> normals = normalsOf(depth, intrinsics, span);
    for (int y = 0; y < kHeight; ++y) {
      for (int x = 0; x < kWidth; ++x) {
        if (normals(x, y).w() == 1.0f) angles.push_back(std::acos(normals(x, y).head<3>().cast<double>().dot(n)));
      }
    }
    std::nth_element(angles.begin(), angles.begin() + angles.size() / 2, angles.end());
    return angles[angles.size() / 2];
  };
  EXPECT_GT(medianAngle(1), 0.5);   // measured 0.54 rad: the plateaus' fronto-parallel normal (31°)
  EXPECT_LT(medianAngle(4), 0.07);  // measured 0.046 rad (2.6°)
}

TEST(NormalMap, ValidityDependsOnZNotOnW) {
  // Later stages may store e.g. a confidence in w; a vertex is valid whenever it lies in front of the camera.
  Image<VertexPixel> vertices(3, 3, VertexPixel::Zero());
  vertices(1, 1) = VertexPixel(0.0f, 0.0f, 1.0f, 0.25f);
  vertices(0, 1) = VertexPixel(-0.01f, 0.0f, 1.0f, 0.0f);
  vertices(2, 1) = VertexPixel(0.01f, 0.0f, 1.0f, 0.0f);
  vertices(1, 0) = VertexPixel(0.0f, -0.01f, 1.0f, 5.0f);
  vertices(1, 2) = VertexPixel(0.0f, 0.01f, 1.0f, 1.0f);
  Image<NormalPixel> normals(3, 3, NormalPixel::Zero());
  normalMapCpu(vertices.view(), {.width = 3, .height = 3}, normals.view());
  EXPECT_EQ(normals(1, 1), NormalPixel(0.0f, 0.0f, -1.0f, 1.0f));
}

TEST(NormalMap, CollinearNeighboursAreDegenerate) {
  Image<VertexPixel> vertices(3, 3, VertexPixel::Zero());
  vertices(1, 1) = VertexPixel(0.0f, 0.0f, 1.0f, 1.0f);
  vertices(0, 1) = VertexPixel(-0.01f, 0.0f, 1.0f, 1.0f);
  vertices(2, 1) = VertexPixel(0.01f, 0.0f, 1.0f, 1.0f);
  vertices(1, 0) = VertexPixel(-0.02f, 0.0f, 1.0f, 1.0f);  // on the same line as the other three
  vertices(1, 2) = VertexPixel(0.02f, 0.0f, 1.0f, 1.0f);
  Image<NormalPixel> normals(3, 3, NormalPixel::Constant(-9.0f));
  normalMapCpu(vertices.view(), {.width = 3, .height = 3}, normals.view());
  EXPECT_EQ(normals(1, 1), NormalPixel::Zero());
}

TEST(NormalMap, ThresholdIsTheParallelogramArea) {
  // Differences of 1 cm × 1 cm span 1e-4 m²: kept at a threshold just below, dropped just above.
  Image<VertexPixel> vertices(3, 3, VertexPixel::Zero());
  vertices(1, 1) = VertexPixel(0.0f, 0.0f, 1.0f, 1.0f);
  vertices(0, 1) = VertexPixel(-0.005f, 0.0f, 1.0f, 1.0f);
  vertices(2, 1) = VertexPixel(0.005f, 0.0f, 1.0f, 1.0f);
  vertices(1, 0) = VertexPixel(0.0f, -0.005f, 1.0f, 1.0f);
  vertices(1, 2) = VertexPixel(0.0f, 0.005f, 1.0f, 1.0f);
  Image<NormalPixel> normals(3, 3, NormalPixel::Zero());
  normalMapCpu(vertices.view(), {.width = 3, .height = 3, .min_cross_norm_m2 = 0.9e-4f}, normals.view());
  EXPECT_EQ(normals(1, 1).w(), 1.0f);
  normalMapCpu(vertices.view(), {.width = 3, .height = 3, .min_cross_norm_m2 = 1.1e-4f}, normals.view());
  EXPECT_EQ(normals(1, 1), NormalPixel::Zero());
}

TEST(NormalMap, RejectsViewsThatDisagreeWithParams) {
  Image<VertexPixel> vertices(kWidth, kHeight, VertexPixel::Zero());
  Image<NormalPixel> normals(kWidth, kHeight - 1, NormalPixel::Zero());
  EXPECT_THROW(normalMapCpu(vertices.view(), normalParams(), normals.view()), std::invalid_argument);
  Image<NormalPixel> right_size(kWidth, kHeight, NormalPixel::Zero());
  EXPECT_THROW(normalMapCpu(vertices.view(), normalParams(0), right_size.view()), std::invalid_argument);
}

}  // namespace
}  // namespace vifusion::preprocess
