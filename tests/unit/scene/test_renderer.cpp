#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "scene_views.hpp"
#include "vifusion/scene/renderer.hpp"

namespace vifusion::scene {
namespace {

using test::iclCamera;

const LivingRoom& room() {
  static const LivingRoom instance;
  return instance;
}

RowPool& pool() {
  static RowPool instance(2);
  return instance;
}

/// A few views from inside the camera region, in several directions.
std::vector<SE3d> views() {
  return {test::furnishedView(), test::whiteWallView(),
          lookAt(Eigen::Vector3d(1.0, 1.4, 1.5), Eigen::Vector3d(0.2, 0.8, -3.2)),
          lookAt(Eigen::Vector3d(2.2, 1.3, 0.0), Eigen::Vector3d(-1.65, 0.8, 0.4)),
          lookAt(Eigen::Vector3d(0.0, 1.7, -1.8), Eigen::Vector3d(1.5, 0.3, 2.8))};
}

TEST(Renderer, BackProjectedDepthLiesOnTheSurface) {
  const PinholeCamera camera = iclCamera();
  const Renderer renderer(room(), pool());
  Image<float> depth_m(camera.width, camera.height);
  Image<std::uint16_t> depth(camera.width, camera.height);
  const double step_m = 1.0 / renderer.options().depth_scale;
  for (const SE3d& T_W_C : views()) {
    renderer.render(T_W_C, camera, {}, depth_m.view());
    renderer.render(T_W_C, camera, {}, depth.view());
    double worst_exact_m = 0.0;
    double worst_quantised_m = 0.0;
    int valid = 0;
    for (int v = 0; v < camera.height; ++v) {
      for (int u = 0; u < camera.width; ++u) {
        const Eigen::Vector2d uv(u, v);
        if (depth_m(u, v) > 0.0F) {
          ++valid;
          const Eigen::Vector3d p_W = T_W_C * camera.backProject(uv, depth_m(u, v));
          worst_exact_m = std::max(worst_exact_m, room().distanceToSurface(p_W));
        }
        if (depth(u, v) > 0) {
          const Eigen::Vector3d p_W = T_W_C * camera.backProject(uv, depth(u, v) * step_m);
          worst_quantised_m = std::max(worst_quantised_m, room().distanceToSurface(p_W));
        }
      }
    }
    EXPECT_EQ(valid, camera.width * camera.height);  // a closed room: every ray hits something
    EXPECT_LT(worst_exact_m, 1e-6);
    EXPECT_LT(worst_quantised_m, step_m);
  }
}

TEST(Renderer, FrontoParallelWallHasTheAnalyticDepth) {
  const PinholeCamera camera = iclCamera();
  const Renderer renderer(room(), pool());
  Image<float> depth_m(camera.width, camera.height);
  Image<std::uint16_t> depth(camera.width, camera.height);
  // 1.55 m from the white wall.
  renderer.render(test::whiteWallView(), camera, {}, depth_m.view());
  renderer.render(test::whiteWallView(), camera, {}, depth.view());
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) {
      ASSERT_NEAR(depth_m(u, v), 1.55, 1e-6) << u << ", " << v;
      ASSERT_EQ(depth(u, v), 7750) << u << ", " << v;
    }
  }
  // Straight up at the ceiling from 1.5 m: 1.2 m everywhere.
  const SE3d up = lookAt(Eigen::Vector3d(1.1, 1.5, -0.2), Eigen::Vector3d(1.1, 2.7, -0.2), Eigen::Vector3d::UnitZ());
  renderer.render(up, camera, {}, depth.view());
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) ASSERT_EQ(depth(u, v), 6000) << u << ", " << v;
  }
}

TEST(Renderer, NegativeFyFlipsTheRows) {
  const PinholeCamera flipped = iclCamera();
  const PinholeCamera upright = test::uprightCamera();
  const Renderer renderer(room(), pool());
  Image<Rgb8> rgb_flipped(640, 480);
  Image<Rgb8> rgb_upright(640, 480);
  Image<std::uint16_t> depth_flipped(640, 480);
  Image<std::uint16_t> depth_upright(640, 480);
  renderer.render(test::furnishedView(), flipped, rgb_flipped.view(), depth_flipped.view());
  renderer.render(test::furnishedView(), upright, rgb_upright.view(), depth_upright.view());
  for (int v = 0; v < 480; ++v) {
    for (int u = 0; u < 640; ++u) {
      ASSERT_EQ(rgb_flipped(u, v), rgb_upright(u, 479 - v)) << u << ", " << v;
      ASSERT_EQ(depth_flipped(u, v), depth_upright(u, 479 - v)) << u << ", " << v;
    }
  }
  // Upright: the floor (brighter, nearer) is at the bottom, the ceiling at the top.
  EXPECT_GT(depth_upright(320, 10), 0);
  EXPECT_NE(rgb_upright(320, 10), rgb_upright(320, 470));
}

TEST(Renderer, WhiteWallIsUniformBeforeNoise) {
  const PinholeCamera camera = iclCamera();
  const Renderer renderer(room(), pool());
  Image<Rgb8> rgb(camera.width, camera.height);
  renderer.render(test::whiteWallView(), camera, rgb.view(), ImageView<std::uint16_t>{});
  // albedo × (ambient + diffuse·(1 + n·l)/2) with n = −x.
  const RenderOptions& o = renderer.options();
  const double facing = -o.light_direction_W.normalized().x();
  const double shade = o.ambient + o.diffuse * 0.5 * (1.0 + facing);
  const auto expected = static_cast<std::uint8_t>(std::lround(235.0 * shade));
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) ASSERT_EQ(rgb(u, v), (Rgb8{expected, expected, expected})) << u << ", " << v;
  }
  // Far from both clamps, so intensity noise there is unbiased.
  EXPECT_GT(expected, 60);
  EXPECT_LT(expected, 200);
}

/// Mean |∇I| at full, half and quarter resolution [grey levels per pixel of that level].
std::array<double, 3> pyramidGradients(const Renderer& renderer, const SE3d& T_W_C) {
  const PinholeCamera camera = iclCamera();
  Image<Rgb8> rgb(camera.width, camera.height);
  renderer.render(T_W_C, camera, rgb.view(), ImageView<std::uint16_t>{});
  const Image<float> level0 = test::grey(rgb);
  const Image<float> level1 = test::halve(level0);
  const Image<float> level2 = test::halve(level1);
  return {test::meanGradient(level0), test::meanGradient(level1), test::meanGradient(level2)};
}

TEST(Renderer, TexturedSurfacesHaveGradientsAtThreePyramidScales) {
  // Bare walls and floor (no furniture), each seen from about 2–3 m, and the furnished room.
  const LivingRoom bare(std::vector<BoxSpec>{});
  const Renderer bare_renderer(bare, pool());
  struct View {
    const char* name;
    SE3d T_W_C;
  };
  const View walls[] = {
      {"north stripes", lookAt(Eigen::Vector3d(1.1, 1.4, -0.8), Eigen::Vector3d(1.1, 1.3, -3.2))},
      {"west panels", lookAt(Eigen::Vector3d(0.6, 1.0, 0.0), Eigen::Vector3d(-1.65, 0.9, 0.0))},
      {"south bricks", lookAt(Eigen::Vector3d(1.1, 1.4, 0.6), Eigen::Vector3d(1.1, 1.3, 2.8))},
      {"floor planks", lookAt(Eigen::Vector3d(1.1, 1.8, 0.0), Eigen::Vector3d(1.1, 0.0, -0.5))},
  };
  // Threshold: a few grey levels per pixel at every level. A smooth shaded wall gives 0, and
  // textures with structure at one scale only fall below it at the other levels.
  constexpr double kMinGradient = 2.0;
  for (const View& view : walls) {
    const std::array<double, 3> g = pyramidGradients(bare_renderer, view.T_W_C);
    std::printf("mean |grad I| %-13s: %.1f, %.1f, %.1f grey levels/px at 640, 320, 160 px\n", view.name, g[0], g[1],
                g[2]);
    for (int level = 0; level < 3; ++level) {
      EXPECT_GT(g[static_cast<std::size_t>(level)], kMinGradient) << view.name << " level " << level;
    }
  }
  const Renderer renderer(room(), pool());
  const std::array<double, 3> furnished = pyramidGradients(renderer, test::furnishedView());
  std::printf("mean |grad I| %-13s: %.1f, %.1f, %.1f grey levels/px at 640, 320, 160 px\n", "furnished", furnished[0],
              furnished[1], furnished[2]);
  for (double g : furnished) EXPECT_GT(g, kMinGradient);
  const std::array<double, 3> white = pyramidGradients(renderer, test::whiteWallView());
  for (double g : white) EXPECT_EQ(g, 0.0);
}

TEST(Renderer, MotionBlurAveragesColourAndTakesDepthFromTheMiddleSample) {
  const PinholeCamera camera = iclCamera();
  const Renderer renderer(room(), pool());
  const SE3d middle = test::furnishedView();
  std::vector<SE3d> samples;
  for (int i = -2; i <= 2; ++i) {
    samples.push_back(SE3d::exp((Vector6d() << 0.01 * i, 0.0, 0.0, 0.0, 0.004 * i, 0.0).finished()) * middle);
  }
  Image<Rgb8> blurred(640, 480);
  Image<std::uint16_t> blurred_depth(640, 480);
  renderer.renderBlurred(samples, camera, blurred.view(), blurred_depth.view());
  std::vector<Image<Rgb8>> sharp(samples.size(), Image<Rgb8>(640, 480));
  for (std::size_t i = 0; i < samples.size(); ++i)
    renderer.render(samples[i], camera, sharp[i].view(), ImageView<std::uint16_t>{});
  Image<std::uint16_t> middle_depth(640, 480);
  renderer.render(samples[2], camera, {}, middle_depth.view());

  int differs = 0;
  for (int v = 0; v < 480; ++v) {
    for (int u = 0; u < 640; ++u) {
      ASSERT_EQ(blurred_depth(u, v), middle_depth(u, v));
      // The mean of the sub-frame colours, within the 8-bit rounding of each.
      double mean_r = 0.0;
      for (const Image<Rgb8>& s : sharp) mean_r += s(u, v).r;
      mean_r /= static_cast<double>(sharp.size());
      ASSERT_NEAR(blurred(u, v).r, mean_r, 1.0) << u << ", " << v;
      differs += blurred(u, v) != sharp[2](u, v);
    }
  }
  EXPECT_GT(differs, 10000);  // the blur is visible

  // Depth alone (the sensor-resolution render of `vifusion sim`) is the same middle-sample depth.
  Image<std::uint16_t> depth_alone(640, 480);
  renderer.renderBlurred(samples, camera, {}, depth_alone.view());
  EXPECT_TRUE(std::equal(depth_alone.data(), depth_alone.data() + depth_alone.pixelCount(), middle_depth.data()));

  // One sample is a plain render.
  Image<Rgb8> single(640, 480);
  renderer.renderBlurred(std::span(&middle, 1), camera, single.view(), ImageView<std::uint16_t>{});
  Image<Rgb8> plain(640, 480);
  renderer.render(middle, camera, plain.view(), ImageView<std::uint16_t>{});
  EXPECT_TRUE(std::equal(single.data(), single.data() + single.pixelCount(), plain.data()));
}

TEST(Renderer, OutputDoesNotDependOnTheThreadCount) {
  const PinholeCamera camera = iclCamera();
  RowPool one(1);
  RowPool three(3);
  Image<Rgb8> rgb_one(640, 480);
  Image<Rgb8> rgb_three(640, 480);
  Image<float> depth_one(640, 480);
  Image<float> depth_three(640, 480);
  Renderer(room(), one).render(test::furnishedView(), camera, rgb_one.view(), depth_one.view());
  Renderer(room(), three).render(test::furnishedView(), camera, rgb_three.view(), depth_three.view());
  EXPECT_TRUE(std::equal(rgb_one.data(), rgb_one.data() + rgb_one.pixelCount(), rgb_three.data()));
  EXPECT_TRUE(std::equal(depth_one.data(), depth_one.data() + depth_one.pixelCount(), depth_three.data()));
}

TEST(Renderer, NoHitOrOutOfRangeReadsZeroDepth) {
  const PinholeCamera camera = iclCamera();
  RenderOptions short_range;
  short_range.max_range_m = 1.0;
  Image<Rgb8> rgb(640, 480);
  Image<std::uint16_t> depth(640, 480);
  // The white wall is 1.55 m away: beyond range, but still seen in colour.
  Renderer(room(), pool(), short_range).render(test::whiteWallView(), camera, rgb.view(), depth.view());
  EXPECT_EQ(*std::max_element(depth.data(), depth.data() + depth.pixelCount()), 0);
  EXPECT_GT(rgb(320, 240).r, 0);
  // Outside the room looking away from it: nothing at all.
  Renderer(room(), pool())
      .render(lookAt(Eigen::Vector3d(6.0, 1.0, 0.0), Eigen::Vector3d(9.0, 1.0, 0.0)), camera, rgb.view(), depth.view());
  EXPECT_EQ(*std::max_element(depth.data(), depth.data() + depth.pixelCount()), 0);
  EXPECT_EQ(rgb(320, 240), (Rgb8{0, 0, 0}));
}

TEST(Renderer, RejectsImagesOfTheWrongSize) {
  const Renderer renderer(room(), pool());
  Image<Rgb8> small(320, 240);
  EXPECT_THROW(renderer.render(test::furnishedView(), iclCamera(), small.view(), ImageView<std::uint16_t>{}),
               std::invalid_argument);
  EXPECT_THROW(renderer.renderBlurred(std::span<const SE3d>{}, iclCamera(), {}, ImageView<std::uint16_t>{}),
               std::invalid_argument);
}

}  // namespace
}  // namespace vifusion::scene
