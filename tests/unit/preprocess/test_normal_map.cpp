#include <gtest/gtest.h>

#include <Eigen/Core>
#include <stdexcept>

#include "synthetic_images.hpp"
#include "vifusion/preprocess/cpu_reference.hpp"

namespace vifusion::preprocess {
namespace {

constexpr int kWidth = 64;
constexpr int kHeight = 48;

VertexMapParams testIntrinsics(float f_px, float fy_sign) {
  return {.width = kWidth, .height = kHeight, .fx = f_px, .fy = fy_sign * f_px, .cx = 31.5f, .cy = 23.5f};
}

NormalMapParams normalParams() {
  NormalMapParams params;
  params.width = kWidth;
  params.height = kHeight;
  return params;
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

Image<NormalPixel> normalsOf(const Image<float>& depth, const VertexMapParams& intrinsics) {
  Image<VertexPixel> vertices(kWidth, kHeight, VertexPixel::Zero());
  vertexMapCpu(depth.view(), intrinsics, vertices.view());
  Image<NormalPixel> normals(kWidth, kHeight, NormalPixel::Constant(-9.0f));
  normalMapCpu(vertices.view(), normalParams(), normals.view());
  return normals;
}

TEST(NormalMap, TiltedPlaneGivesTheAnalyticNormalForEitherSignOfFy) {
  const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.4, -1.0).normalized();  // faces the camera: n·p < 0
  const Eigen::Vector3d p0(0.0, 0.0, 2.0);
  for (const float fy_sign : {1.0f, -1.0f}) {
    // f = 52.5 px keeps neighbouring vertices ~4 cm apart, so float rounding of the vertices
    // perturbs the forward differences by only ~1e-5 relative.
    const VertexMapParams intrinsics = testIntrinsics(52.5f, fy_sign);
    const Image<NormalPixel> normals = normalsOf(planeDepth(n, p0, intrinsics), intrinsics);
    for (int y = 0; y + 1 < kHeight; ++y) {
      for (int x = 0; x + 1 < kWidth; ++x) {
        const NormalPixel& normal = normals(x, y);
        ASSERT_EQ(normal.w(), 1.0f) << x << "," << y;
        EXPECT_NEAR(normal.x(), n.x(), 1e-4) << "fy sign " << fy_sign << " at " << x << "," << y;
        EXPECT_NEAR(normal.y(), n.y(), 1e-4) << "fy sign " << fy_sign << " at " << x << "," << y;
        EXPECT_NEAR(normal.z(), n.z(), 1e-4) << "fy sign " << fy_sign << " at " << x << "," << y;
        EXPECT_NEAR(normal.head<3>().norm(), 1.0f, 1e-6f);
      }
    }
  }
}

TEST(NormalMap, RealisticFocalLengthStillGivesTheAnalyticNormal) {
  // f = 525 px: neighbours ~4 mm apart at 2 m, float vertices limit the accuracy to ~1e-4.
  const Eigen::Vector3d n = Eigen::Vector3d(-0.2, 0.5, -1.0).normalized();
  const VertexMapParams intrinsics = testIntrinsics(525.0f, 1.0f);
  const Image<NormalPixel> normals = normalsOf(planeDepth(n, Eigen::Vector3d(0.1, 0.0, 2.0), intrinsics), intrinsics);
  for (int y = 0; y + 1 < kHeight; ++y) {
    for (int x = 0; x + 1 < kWidth; ++x) {
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
    for (int y = 0; y + 1 < kHeight; ++y) {
      for (int x = 0; x + 1 < kWidth; ++x) {
        EXPECT_EQ(normals(x, y), NormalPixel(0.0f, 0.0f, -1.0f, 1.0f)) << "fy sign " << fy_sign << " at " << x << "," << y;
      }
    }
  }
}

TEST(NormalMap, LastColumnAndLastRowAreInvalid) {
  const VertexMapParams intrinsics = testIntrinsics(52.5f, 1.0f);
  const Image<NormalPixel> normals = normalsOf(Image<float>(kWidth, kHeight, 1.0f), intrinsics);
  for (int y = 0; y < kHeight; ++y) EXPECT_EQ(normals(kWidth - 1, y), NormalPixel::Zero()) << y;
  for (int x = 0; x < kWidth; ++x) EXPECT_EQ(normals(x, kHeight - 1), NormalPixel::Zero()) << x;
}

TEST(NormalMap, AHoleInvalidatesItsPixelAndThePixelsThatDifferenceAcrossIt) {
  Image<float> depth(kWidth, kHeight, 1.0f);
  depth(5, 5) = 0.0f;
  const Image<NormalPixel> normals = normalsOf(depth, testIntrinsics(52.5f, 1.0f));
  EXPECT_EQ(normals(5, 5), NormalPixel::Zero());
  EXPECT_EQ(normals(4, 5), NormalPixel::Zero());  // right neighbour missing
  EXPECT_EQ(normals(5, 4), NormalPixel::Zero());  // lower neighbour missing
  EXPECT_EQ(normals(4, 4).w(), 1.0f);
  EXPECT_EQ(normals(6, 5).w(), 1.0f);
  EXPECT_EQ(normals(5, 6).w(), 1.0f);
}

TEST(NormalMap, ValidityDependsOnZNotOnW) {
  // Later stages may store e.g. a confidence in w; a vertex is valid whenever it lies in front of the camera.
  Image<VertexPixel> vertices(2, 2, VertexPixel::Zero());
  vertices(0, 0) = VertexPixel(0.0f, 0.0f, 1.0f, 0.25f);
  vertices(1, 0) = VertexPixel(0.01f, 0.0f, 1.0f, 0.0f);
  vertices(0, 1) = VertexPixel(0.0f, 0.01f, 1.0f, 5.0f);
  vertices(1, 1) = VertexPixel(0.01f, 0.01f, 1.0f, 1.0f);
  Image<NormalPixel> normals(2, 2, NormalPixel::Zero());
  normalMapCpu(vertices.view(), {.width = 2, .height = 2}, normals.view());
  EXPECT_EQ(normals(0, 0), NormalPixel(0.0f, 0.0f, -1.0f, 1.0f));
}

TEST(NormalMap, CollinearNeighboursAreDegenerate) {
  Image<VertexPixel> vertices(2, 2, VertexPixel::Zero());
  vertices(0, 0) = VertexPixel(0.0f, 0.0f, 1.0f, 1.0f);
  vertices(1, 0) = VertexPixel(0.01f, 0.0f, 1.0f, 1.0f);
  vertices(0, 1) = VertexPixel(0.02f, 0.0f, 1.0f, 1.0f);  // on the same line as the other two
  vertices(1, 1) = VertexPixel(0.01f, 0.01f, 1.0f, 1.0f);
  Image<NormalPixel> normals(2, 2, NormalPixel::Constant(-9.0f));
  normalMapCpu(vertices.view(), {.width = 2, .height = 2}, normals.view());
  EXPECT_EQ(normals(0, 0), NormalPixel::Zero());
}

TEST(NormalMap, ThresholdIsTheParallelogramArea) {
  // Differences of 1 cm × 1 cm span 1e-4 m²: kept at a threshold just below, dropped just above.
  Image<VertexPixel> vertices(2, 2, VertexPixel::Zero());
  vertices(0, 0) = VertexPixel(0.0f, 0.0f, 1.0f, 1.0f);
  vertices(1, 0) = VertexPixel(0.01f, 0.0f, 1.0f, 1.0f);
  vertices(0, 1) = VertexPixel(0.0f, 0.01f, 1.0f, 1.0f);
  vertices(1, 1) = VertexPixel(0.01f, 0.01f, 1.0f, 1.0f);
  Image<NormalPixel> normals(2, 2, NormalPixel::Zero());
  normalMapCpu(vertices.view(), {.width = 2, .height = 2, .min_cross_norm_m2 = 0.9e-4f}, normals.view());
  EXPECT_EQ(normals(0, 0).w(), 1.0f);
  normalMapCpu(vertices.view(), {.width = 2, .height = 2, .min_cross_norm_m2 = 1.1e-4f}, normals.view());
  EXPECT_EQ(normals(0, 0), NormalPixel::Zero());
}

TEST(NormalMap, RejectsViewsThatDisagreeWithParams) {
  Image<VertexPixel> vertices(kWidth, kHeight, VertexPixel::Zero());
  Image<NormalPixel> normals(kWidth, kHeight - 1, NormalPixel::Zero());
  EXPECT_THROW(normalMapCpu(vertices.view(), normalParams(), normals.view()), std::invalid_argument);
}

}  // namespace
}  // namespace vifusion::preprocess
