// Colour antialiasing: a pixel's colour should be what a camera pixel integrates, the scene averaged
// over the pixel's area, not a point sample that aliases fine texture differently from every view
// (which biases photometric tracking on synthetic data).

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "scene_views.hpp"
#include "vifusion/scene/counter_rng.hpp"
#include "vifusion/scene/pixel_footprint.hpp"
#include "vifusion/scene/renderer.hpp"
#include "vifusion/scene/texture.hpp"

namespace vifusion::scene {
namespace {

using test::pool;
using test::room;

using test::iclCamera;

const LivingRoom& bareRoom() {
  static const LivingRoom instance(std::vector<BoxSpec>{});
  return instance;
}

/// The renderer as it was before antialiasing: one ray through the pixel centre, point-sampled textures.
RenderOptions pointSampled() {
  RenderOptions options;
  options.filter_textures = false;
  options.edge_samples_per_axis = 1;
  return options;
}

/// Pixels the reference is computed at: every kStride-th column and row (the brute force is slow).
constexpr int kStride = 4;
/// The reference is the mean of kReference × kReference stratified rays with point-sampled textures.
constexpr int kReference = 8;

/// Brute-force box mean of the shaded scene over pixel (u, v) on the 0–255 scale, per channel.
Eigen::Vector3d referencePixel(const LivingRoom& scene, const RenderOptions& options, const SE3d& T_W_C,
                               const PinholeCamera& camera, int u, int v) {
  const Eigen::Matrix3d R_W_C = T_W_C.rotationMatrix();
  const Eigen::Vector3d light_W = options.light_direction_W.normalized();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int j = 0; j < kReference; ++j) {
    for (int k = 0; k < kReference; ++k) {
      const double x_n = (u - camera.cx + (k + 0.5) / kReference - 0.5) / camera.fx;
      const double y_n = (v - camera.cy + (j + 0.5) / kReference - 0.5) / camera.fy;
      SurfaceHit hit;
      if (!scene.intersect(T_W_C.translation(), R_W_C.col(2) + x_n * R_W_C.col(0) + y_n * R_W_C.col(1), &hit)) continue;
      const double shade = options.ambient + options.diffuse * 0.5 * (1.0 + hit.normal_W.dot(light_W));
      sum += albedo(hit.material, hit.variant, hit.st_m).cast<double>() * shade;
    }
  }
  return sum * (255.0 / (kReference * kReference));
}

/// RMS difference [0–255 grey levels, over channels and the reference pixels] between a render with
/// `options` and the brute-force reference.
struct Comparison {
  double antialiased_rms = 0.0;
  double point_sampled_rms = 0.0;
};

Comparison compareWithReference(const LivingRoom& scene, const SE3d& T_W_C) {
  const PinholeCamera camera = iclCamera();
  RenderOptions options;
  options.optics_blur_sigma_px = 0.0;  // the pixel's own box, which the reference integrates
  Image<Rgb8> antialiased(camera.width, camera.height);
  Image<Rgb8> point_sampled(camera.width, camera.height);
  Renderer(scene, pool(), options).render(T_W_C, camera, antialiased.view(), ImageView<std::uint16_t>{});
  Renderer(scene, pool(), pointSampled()).render(T_W_C, camera, point_sampled.view(), ImageView<std::uint16_t>{});

  const int columns = camera.width / kStride;
  const int rows = camera.height / kStride;
  Image<Eigen::Vector3d> reference(columns, rows, Eigen::Vector3d::Zero());
  pool().forRows(rows, [&](int row_begin, int row_end) {
    for (int y = row_begin; y < row_end; ++y) {
      for (int x = 0; x < columns; ++x) {
        reference(x, y) =
            referencePixel(scene, options, T_W_C, camera, kStride * x + kStride / 2, kStride * y + kStride / 2);
      }
    }
  });
  const auto rms = [&](const Image<Rgb8>& image) {
    double sum = 0.0;
    for (int y = 0; y < rows; ++y) {
      for (int x = 0; x < columns; ++x) {
        const Rgb8 p = image(kStride * x + kStride / 2, kStride * y + kStride / 2);
        sum += (Eigen::Vector3d(p.r, p.g, p.b) - reference(x, y)).squaredNorm();
      }
    }
    return std::sqrt(sum / (3.0 * columns * rows));
  };
  return {rms(antialiased), rms(point_sampled)};
}

TEST(Antialiasing, ColourIsThePixelMeanOfTheScene) {
  struct View {
    const char* name;
    const LivingRoom& scene;
    SE3d T_W_C;
  };
  const View views[] = {
      {"furnished", room(), test::furnishedView()},
      // Textured walls far away: 1–2 cm detail spans about a pixel.
      {"far stripes", bareRoom(), lookAt(Eigen::Vector3d(1.1, 1.4, 2.4), Eigen::Vector3d(1.1, 1.3, -3.2))},
      {"far bricks", bareRoom(), lookAt(Eigen::Vector3d(1.1, 1.4, -2.8), Eigen::Vector3d(1.1, 1.3, 2.8))},
      // Floor planks and rug at grazing angles, ceiling tiles overhead.
      {"grazing floor", room(), lookAt(Eigen::Vector3d(2.2, 1.7, 1.5), Eigen::Vector3d(-1.0, 0.2, -3.0))},
      {"ceiling", room(), lookAt(Eigen::Vector3d(1.0, 1.2, 1.5), Eigen::Vector3d(0.5, 2.7, -3.0))},
  };
  // The reference's own Monte-Carlo error is far below these: 64 stratified samples per pixel.
  constexpr double kMaxAntialiasedRms = 2.0;
  constexpr double kMinPointSampledRms = 3.0;
  for (const View& view : views) {
    const Comparison c = compareWithReference(view.scene, view.T_W_C);
    std::printf("RMS against the %dx%d-ray pixel mean, %-13s: antialiased %.2f, point-sampled %.2f grey levels\n",
                kReference, kReference, view.name, c.antialiased_rms, c.point_sampled_rms);
    EXPECT_LT(c.antialiased_rms, kMaxAntialiasedRms) << view.name;
    // The point-sampled render (the renderer before antialiasing) is far off: the test can tell.
    EXPECT_GT(c.point_sampled_rms, kMinPointSampledRms) << view.name;
  }
}

/// RMS [grey levels] of B − (A(u − 1) + A(u))/2 over the interior, where B is A's view moved half a
/// pixel to the right: how well an image predicts itself after a sub-pixel shift, which is what
/// photometric alignment relies on. Aliasing makes the two renders disagree; so, less, does genuine
/// detail near the Nyquist frequency, which linear interpolation cannot reproduce.
double halfPixelShiftRms(const RenderOptions& options, const SE3d& T_W_C) {
  const PinholeCamera camera = iclCamera();
  PinholeCamera shifted = camera;
  shifted.cx += 0.5;  // pixel u of the shifted camera sees what pixel u − ½ of the original sees
  const Renderer renderer(bareRoom(), pool(), options);
  Image<Rgb8> a(camera.width, camera.height);
  Image<Rgb8> b(camera.width, camera.height);
  renderer.render(T_W_C, camera, a.view(), ImageView<std::uint16_t>{});
  renderer.render(T_W_C, shifted, b.view(), ImageView<std::uint16_t>{});
  const Image<float> grey_a = test::grey(a);
  const Image<float> grey_b = test::grey(b);
  double sum = 0.0;
  int count = 0;
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 1; u < camera.width; ++u) {
      const double predicted = 0.5 * (grey_a(u - 1, v) + grey_a(u, v));
      sum += (grey_b(u, v) - predicted) * (grey_b(u, v) - predicted);
      ++count;
    }
  }
  return std::sqrt(sum / count);
}

TEST(Antialiasing, HalfPixelShiftIsPredictedByInterpolation) {
  // Far textured walls, where 1–2 cm detail spans about a pixel.
  const SE3d views[] = {lookAt(Eigen::Vector3d(1.1, 1.4, 2.4), Eigen::Vector3d(1.1, 1.3, -3.2)),
                        lookAt(Eigen::Vector3d(1.1, 1.4, -2.8), Eigen::Vector3d(1.1, 1.3, 2.8))};
  RenderOptions sharp;
  sharp.optics_blur_sigma_px = 0.0;
  for (const SE3d& T_W_C : views) {
    const double antialiased = halfPixelShiftRms(RenderOptions{}, T_W_C);
    const double pixel_box_only = halfPixelShiftRms(sharp, T_W_C);
    const double point_sampled = halfPixelShiftRms(pointSampled(), T_W_C);
    std::printf("half-pixel shift: antialiased %.2f, without optics blur %.2f, point-sampled %.2f grey levels RMS\n",
                antialiased, pixel_box_only, point_sampled);
    EXPECT_LT(antialiased, 0.4 * point_sampled);
    EXPECT_LT(pixel_box_only, 0.6 * point_sampled);
  }
}

TEST(Antialiasing, FilteredTextureIsTheMeanOverTheFootprint) {
  // Axis-aligned footprints from 1 mm to 3 cm (a pixel at 0.5–15 m head-on) at random points of every
  // material: the filtered albedo must be much closer to the brute-force footprint mean than the
  // point sample is.
  constexpr int kGrid = 24;
  const Material materials[] = {
      Material::kWallStripes, Material::kWallPanels, Material::kWallBricks, Material::kFloorPlanks, Material::kCeiling,
      Material::kRug,         Material::kFabric,     Material::kWood,       Material::kPaintedWood, Material::kBook,
      Material::kCanvas,      Material::kMetal,      Material::kLeaves,     Material::kLampShade,   Material::kScreen};
  for (const Material material : materials) {
    double filtered_sq = 0.0;
    double point_sq = 0.0;
    for (std::uint64_t i = 0; i < 400; ++i) {
      const Eigen::Vector2d st_m(0.01 * static_cast<double>(counterBits(1, i, 0) % 300),
                                 0.01 * static_cast<double>(counterBits(2, i, 0) % 250) + 0.013 * (i % 7));
      const double width_m = 0.001 * std::pow(30.0, static_cast<double>(counterBits(3, i, 0) % 1000) / 1000.0);
      const Eigen::Matrix2d J_st_px = Eigen::Vector2d(width_m, width_m * (0.5 + (i % 3) * 0.5)).asDiagonal();
      const auto variant = static_cast<std::uint32_t>(i % 5);
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (int j = 0; j < kGrid; ++j) {
        for (int k = 0; k < kGrid; ++k) {
          const Eigen::Vector2d offset_px((k + 0.5) / kGrid - 0.5, (j + 0.5) / kGrid - 0.5);
          mean += albedo(material, variant, st_m + J_st_px * offset_px).cast<double>();
        }
      }
      mean /= kGrid * kGrid;
      filtered_sq += (albedo(material, variant, st_m, J_st_px).cast<double>() - mean).squaredNorm();
      point_sq += (albedo(material, variant, st_m).cast<double>() - mean).squaredNorm();
    }
    const double filtered_rms = 255.0 * std::sqrt(filtered_sq / 1200.0);
    const double point_rms = 255.0 * std::sqrt(point_sq / 1200.0);
    std::printf("footprint mean, material %2d: filtered %.2f, point %.2f grey levels RMS\n", static_cast<int>(material),
                filtered_rms, point_rms);
    EXPECT_LT(filtered_rms, 0.35 * point_rms) << "material " << static_cast<int>(material);
  }
}

TEST(Antialiasing, FootprintMatchesFiniteDifferencesOfHits) {
  const PinholeCamera camera = iclCamera();
  const SE3d T_W_C = test::furnishedView();
  const Eigen::Matrix3d R_W_C = T_W_C.rotationMatrix();
  const auto direction = [&](double u, double v) {
    return Eigen::Vector3d(R_W_C.col(2) + (u - camera.cx) / camera.fx * R_W_C.col(0) +
                           (v - camera.cy) / camera.fy * R_W_C.col(1));
  };
  constexpr double kStep_px = 1e-3;
  int checked = 0;
  for (int v = 5; v < camera.height; v += 37) {
    for (int u = 3; u < camera.width; u += 41) {
      SurfaceHit hit;
      SurfaceHit du_plus;
      SurfaceHit du_minus;
      SurfaceHit dv_plus;
      SurfaceHit dv_minus;
      ASSERT_TRUE(room().intersect(T_W_C.translation(), direction(u, v), &hit));
      room().intersect(T_W_C.translation(), direction(u + kStep_px, v), &du_plus);
      room().intersect(T_W_C.translation(), direction(u - kStep_px, v), &du_minus);
      room().intersect(T_W_C.translation(), direction(u, v + kStep_px), &dv_plus);
      room().intersect(T_W_C.translation(), direction(u, v - kStep_px), &dv_minus);
      if (!sameFace(hit, du_plus) || !sameFace(hit, du_minus) || !sameFace(hit, dv_plus) || !sameFace(hit, dv_minus)) {
        continue;  // on an edge: no derivative
      }
      Eigen::Matrix2d numeric;
      numeric << (du_plus.st_m - du_minus.st_m) / (2 * kStep_px), (dv_plus.st_m - dv_minus.st_m) / (2 * kStep_px);
      const Eigen::Matrix2d J_st_px =
          stJacobian(hit, direction(u, v), R_W_C.col(0) / camera.fx, R_W_C.col(1) / camera.fy);
      ASSERT_LT((J_st_px - numeric).norm(), 1e-6 * (1.0 + numeric.norm())) << u << ", " << v;
      ++checked;
    }
  }
  EXPECT_GT(checked, 150);
}

TEST(Antialiasing, PointSampledOptionsGiveTheOneRayRender) {
  // filter_textures = false and one edge sample reproduce the renderer before antialiasing: every
  // pixel is the centre ray's point-sampled colour.
  const PinholeCamera camera = iclCamera();
  const SE3d T_W_C = test::furnishedView();
  const RenderOptions options = pointSampled();
  Image<Rgb8> rgb(camera.width, camera.height);
  Renderer(room(), pool(), options).render(T_W_C, camera, rgb.view(), ImageView<std::uint16_t>{});
  const Eigen::Matrix3d R_W_C = T_W_C.rotationMatrix();
  const Eigen::Vector3d light_W = options.light_direction_W.normalized();
  for (int v = 0; v < camera.height; v += 7) {
    for (int u = 0; u < camera.width; u += 5) {
      const double x_n = (u - camera.cx) / camera.fx;
      const double y_n = (v - camera.cy) / camera.fy;
      SurfaceHit hit;
      ASSERT_TRUE(room().intersect(T_W_C.translation(), R_W_C.col(2) + x_n * R_W_C.col(0) + y_n * R_W_C.col(1), &hit));
      const auto facing = static_cast<float>(hit.normal_W.dot(light_W));
      const Albedo colour = albedo(hit.material, hit.variant, hit.st_m) *
                            static_cast<float>(options.ambient + options.diffuse * 0.5 * (1.0 + facing));
      const Rgb8 p = rgb(u, v);
      ASSERT_NEAR(p.r, 255.0F * colour.x(), 0.5F + 1e-3F) << u << ", " << v;
      ASSERT_NEAR(p.g, 255.0F * colour.y(), 0.5F + 1e-3F) << u << ", " << v;
      ASSERT_NEAR(p.b, 255.0F * colour.z(), 0.5F + 1e-3F) << u << ", " << v;
    }
  }
}

TEST(Antialiasing, DepthIsTheCentreRayWhateverTheColourOptions) {
  const PinholeCamera camera = iclCamera();
  Image<Rgb8> rgb(camera.width, camera.height);
  Image<float> antialiased(camera.width, camera.height);
  Image<float> point_sampled(camera.width, camera.height);
  Renderer(room(), pool()).render(test::furnishedView(), camera, rgb.view(), antialiased.view());
  Renderer(room(), pool(), pointSampled()).render(test::furnishedView(), camera, {}, point_sampled.view());
  EXPECT_TRUE(std::equal(antialiased.data(), antialiased.data() + antialiased.pixelCount(), point_sampled.data()));
}

TEST(Antialiasing, RejectsBadOptions) {
  RenderOptions none;
  none.edge_samples_per_axis = 0;
  EXPECT_THROW(none.validate(), std::invalid_argument);
  RenderOptions too_many;
  too_many.edge_samples_per_axis = RenderOptions::kMaxEdgeSamplesPerAxis + 1;
  EXPECT_THROW(Renderer(room(), pool(), too_many), std::invalid_argument);
  RenderOptions no_scale;
  no_scale.depth_scale = 0.0;
  EXPECT_THROW(no_scale.validate(), std::invalid_argument);
  RenderOptions negative_blur;
  negative_blur.optics_blur_sigma_px = -0.1;
  EXPECT_THROW(negative_blur.validate(), std::invalid_argument);
  EXPECT_NO_THROW(RenderOptions{}.validate());
}

}  // namespace
}  // namespace vifusion::scene
