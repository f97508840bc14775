#include <gtest/gtest.h>

#include <stdexcept>

#include "synthetic_images.hpp"
#include "vifusion/preprocess/cpu_reference.hpp"

namespace vifusion::preprocess {
namespace {

constexpr int kWidth = 64;
constexpr int kHeight = 48;

VertexMapParams testIntrinsics(float fy) {
  return {.width = kWidth, .height = kHeight, .fx = 52.5f, .fy = fy, .cx = 31.5f, .cy = 23.25f};
}

TEST(VertexMap, FromCameraCopiesTheIntrinsics) {
  PinholeCamera camera;
  camera.width = 640;
  camera.height = 480;
  camera.fx = 481.2;
  camera.fy = -480.0;
  camera.cx = 319.5;
  camera.cy = 239.5;
  const VertexMapParams params = VertexMapParams::fromCamera(camera);
  EXPECT_EQ(params.width, 640);
  EXPECT_EQ(params.height, 480);
  EXPECT_FLOAT_EQ(params.fx, 481.2f);
  EXPECT_FLOAT_EQ(params.fy, -480.0f);
  EXPECT_FLOAT_EQ(params.cx, 319.5f);
  EXPECT_FLOAT_EQ(params.cy, 239.5f);
}

TEST(VertexMap, FrontoParallelPlane) {
  Image<float> depth(kWidth, kHeight, 2.0f);
  Image<VertexPixel> vertices(kWidth, kHeight, VertexPixel::Zero());
  const VertexMapParams params = testIntrinsics(50.0f);
  vertexMapCpu(depth.view(), params, vertices.view());
  for (int v = 0; v < kHeight; ++v) {
    for (int u = 0; u < kWidth; ++u) {
      const VertexPixel& p = vertices(u, v);
      EXPECT_NEAR(p.x(), (u - 31.5) / 52.5 * 2.0, 1e-6) << u << "," << v;
      EXPECT_NEAR(p.y(), (v - 23.25) / 50.0 * 2.0, 1e-6) << u << "," << v;
      EXPECT_EQ(p.z(), 2.0f);
      EXPECT_EQ(p.w(), 1.0f);
    }
  }
}

TEST(VertexMap, ProjectingTheVertexGivesBackThePixel) {
  Image<float> depth(kWidth, kHeight);
  test::fillImage(depth, [](int u, int v) { return 0.5f + 0.05f * static_cast<float>(u) + 0.02f * static_cast<float>(v); });
  Image<VertexPixel> vertices(kWidth, kHeight, VertexPixel::Zero());
  for (const float fy : {50.0f, -50.0f}) {
    const VertexMapParams params = testIntrinsics(fy);
    vertexMapCpu(depth.view(), params, vertices.view());
    for (int v = 0; v < kHeight; ++v) {
      for (int u = 0; u < kWidth; ++u) {
        const VertexPixel& p = vertices(u, v);
        EXPECT_NEAR(params.fx * p.x() / p.z() + params.cx, static_cast<float>(u), 1e-4f);
        EXPECT_NEAR(params.fy * p.y() / p.z() + params.cy, static_cast<float>(v), 1e-4f);
      }
    }
  }
}

TEST(VertexMap, NegativeFyMirrorsY) {
  Image<float> depth(kWidth, kHeight, 1.5f);
  Image<VertexPixel> up(kWidth, kHeight, VertexPixel::Zero());
  Image<VertexPixel> down(kWidth, kHeight, VertexPixel::Zero());
  vertexMapCpu(depth.view(), testIntrinsics(50.0f), up.view());
  vertexMapCpu(depth.view(), testIntrinsics(-50.0f), down.view());
  for (int v = 0; v < kHeight; ++v) {
    for (int u = 0; u < kWidth; ++u) {
      EXPECT_EQ(down(u, v).x(), up(u, v).x());
      EXPECT_EQ(down(u, v).y(), -up(u, v).y());
      EXPECT_EQ(down(u, v).z(), up(u, v).z());
    }
  }
}

TEST(VertexMap, InvalidDepthGivesZeroVertex) {
  Image<float> depth(kWidth, kHeight, 1.0f);
  depth(3, 4) = 0.0f;
  depth(5, 6) = -1.0f;
  Image<VertexPixel> vertices(kWidth, kHeight, VertexPixel::Constant(7.0f));
  vertexMapCpu(depth.view(), testIntrinsics(50.0f), vertices.view());
  EXPECT_EQ(vertices(3, 4), VertexPixel::Zero());
  EXPECT_EQ(vertices(5, 6), VertexPixel::Zero());
  EXPECT_EQ(vertices(4, 4).w(), 1.0f);
}

TEST(VertexMap, RejectsViewsThatDisagreeWithParams) {
  Image<float> depth(kWidth, kHeight, 1.0f);
  Image<VertexPixel> vertices(kWidth + 1, kHeight, VertexPixel::Zero());
  EXPECT_THROW(vertexMapCpu(depth.view(), testIntrinsics(50.0f), vertices.view()), std::invalid_argument);
}

}  // namespace
}  // namespace vifusion::preprocess
