// Depth registered to the colour camera (registerDepthToColourCpu, the CPU reference of
// shaders/register_depth.comp) on analytic scenes whose answer follows from the geometry.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <map>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>

#include "synthetic_images.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/preprocess/cpu_reference.hpp"
#include "vifusion/preprocess/depth_registration.hpp"
#include "vifusion/test/counting_allocations.hpp"

namespace vifusion::preprocess {
namespace {

constexpr double kDepthScale_m = 0.001;
constexpr std::uint16_t kNear_units = 1000;
constexpr std::uint16_t kFar_units = 3000;
/// Analytic projections closer than this to a rounding boundary (half-integer) are not judged: float
/// and double may round them to either side.
constexpr double kTieMargin = 1e-3;

PinholeCamera depthCamera() { return PinholeCamera::create(80, 60, 70.0, 70.0, 39.5, 29.5); }

/// A registration between two copies of the depth camera, moved by T_C_D.
DepthRegistration sameIntrinsics(const SE3d& T_C_D) { return {depthCamera(), depthCamera(), T_C_D, kDepthScale_m}; }

SE3d translation(double x_m, double y_m, double z_m) {
  return SE3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(x_m, y_m, z_m));
}

Image<std::uint16_t> constantDepth(const PinholeCamera& camera, std::uint16_t raw) {
  return Image<std::uint16_t>(camera.width, camera.height, raw);
}

std::size_t countNonZero(const Image<std::uint16_t>& image) {
  std::size_t n = 0;
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) n += image(x, y) != 0;
  }
  return n;
}

bool nearTie(double value) { return std::abs(value - std::floor(value) - 0.5) < kTieMargin; }

TEST(RegisterDepth, IdentityIsExactAndRecognised) {
  const DepthRegistration registration = sameIntrinsics(SE3d());
  EXPECT_TRUE(registration.isIdentity());
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> raw(0, 65535);
  Image<std::uint16_t> depth(80, 60);
  test::fillImage(depth, [&](int, int) { return static_cast<std::uint16_t>(raw(rng) < 6000 ? 0 : raw(rng)); });
  Image<std::uint16_t> registered(80, 60, 7);
  registerDepthToColourCpu(depth.view(), registration, registered.view());
  for (int y = 0; y < 60; ++y) {
    for (int x = 0; x < 80; ++x) ASSERT_EQ(registered(x, y), depth(x, y)) << x << "," << y;
  }
  EXPECT_GT(countNonZero(depth), 4000u);
}

TEST(RegisterDepth, AnyRealMotionOrIntrinsicsChangeIsNotIdentity) {
  EXPECT_FALSE(sameIntrinsics(translation(1e-6, 0.0, 0.0)).isIdentity());
  EXPECT_FALSE(sameIntrinsics(
                   SE3d(Eigen::Quaterniond(Eigen::AngleAxisd(1e-6, Eigen::Vector3d::UnitY())), Eigen::Vector3d::Zero()))
                   .isIdentity());
  DepthRegistration other_focal = sameIntrinsics(SE3d());
  other_focal.colour.fx = 70.5;
  EXPECT_FALSE(other_focal.isIdentity());
}

// A tilted plane seen by the depth camera, registered to a colour camera with other intrinsics, 25 mm
// to the side and turned by 2°: every depth pixel must land on the colour pixel nearest to its exact
// (double) projection, carrying its exact depth along the colour axis rounded to units.
TEST(RegisterDepth, TiltedPlaneLandsWhereGeometrySays) {
  const PinholeCamera depth_camera = depthCamera();
  // Denser colour sampling (f 90 vs 70 px): no two depth pixels share a colour pixel.
  const PinholeCamera colour_camera = PinholeCamera::create(96, 72, 90.0, 90.0, 47.3, 35.8);
  const SE3d T_C_D(Eigen::Quaterniond(Eigen::AngleAxisd(2.0 * std::numbers::pi / 180.0, Eigen::Vector3d::UnitY())),
                   Eigen::Vector3d(-0.025, 0.003, 0.001));
  const DepthRegistration registration{depth_camera, colour_camera, T_C_D, kDepthScale_m};
  const Eigen::Vector3d n_D = Eigen::Vector3d(0.2, -0.1, 1.0).normalized();
  constexpr double kPlaneDistance_m = 1.2;

  Image<std::uint16_t> depth(depth_camera.width, depth_camera.height);
  test::fillImage(depth, [&](int u, int v) {
    const Eigen::Vector3d ray = depth_camera.backProject(Eigen::Vector2d(u, v), 1.0);
    return static_cast<std::uint16_t>(std::lround(kPlaneDistance_m / n_D.dot(ray) / kDepthScale_m));
  });
  Image<std::uint16_t> registered(colour_camera.width, colour_camera.height);
  registerDepthToColourCpu(depth.view(), registration, registered.view());

  std::map<std::pair<int, int>, double> expected_units;  // colour pixel → smallest exact depth landing there
  double max_offset_px = 0.0;
  double max_depth_error_units = 0.0;
  int judged = 0;
  int ties = 0;
  for (int v = 0; v < depth_camera.height; ++v) {
    for (int u = 0; u < depth_camera.width; ++u) {
      const Eigen::Vector3d p_C = T_C_D * depth_camera.backProject(Eigen::Vector2d(u, v), depth(u, v) * kDepthScale_m);
      const Eigen::Vector2d uv_C = colour_camera.project(p_C);
      if (nearTie(uv_C.x()) || nearTie(uv_C.y())) {
        ++ties;
        continue;
      }
      const int x = static_cast<int>(std::floor(uv_C.x() + 0.5));
      const int y = static_cast<int>(std::floor(uv_C.y() + 0.5));
      if (x < 0 || x >= colour_camera.width || y < 0 || y >= colour_camera.height) continue;
      auto [it, inserted] = expected_units.try_emplace({x, y}, p_C.z() / kDepthScale_m);
      if (!inserted) it->second = std::min(it->second, p_C.z() / kDepthScale_m);
      ASSERT_NE(registered(x, y), 0) << "depth pixel " << u << "," << v << " → " << uv_C.transpose();
      max_depth_error_units = std::max(max_depth_error_units, std::abs(registered(x, y) - it->second));
      max_offset_px = std::max({max_offset_px, std::abs(uv_C.x() - x), std::abs(uv_C.y() - y)});
      ++judged;
    }
  }
  EXPECT_EQ(expected_units.size(), static_cast<std::size_t>(judged)) << "the scene was meant to have no collisions";
  EXPECT_GT(judged, 4000);  // of 4800 depth pixels: the plane fills most of the colour view
  EXPECT_LE(max_offset_px, 0.5);
  EXPECT_LE(max_depth_error_units, 0.5 + kTieMargin);  // rounded to units, nothing more
  // Nothing lands anywhere else (each tie the loop left unjudged may add one pixel).
  EXPECT_GE(countNonZero(registered), expected_units.size());
  EXPECT_LE(countNonZero(registered), expected_units.size() + ties);
  std::cout << "plane: " << judged << " depth pixels judged (" << ties
            << " ties left out), max |uv_exact − landed| = " << max_offset_px << " px, max depth error "
            << max_depth_error_units << " units, " << countNonZero(registered) << " colour pixels filled\n";
}

// Colour at half the depth resolution: each colour pixel receives a 2 × 2 block of depth pixels, half
// near and half far (a checkerboard), and must keep the near one whichever the scan meets first.
TEST(RegisterDepth, OcclusionKeepsTheNearerSurfaceInAnyOrder) {
  const PinholeCamera depth_camera = depthCamera();
  // u_C = u/2 − 0.15: depth columns 2j and 2j + 1 both round to colour column j (no ties).
  const PinholeCamera colour_camera = PinholeCamera::create(40, 30, 35.0, 35.0, 19.6, 14.6);
  const DepthRegistration registration{depth_camera, colour_camera, SE3d(), kDepthScale_m};
  for (int near_parity : {0, 1}) {
    Image<std::uint16_t> depth(depth_camera.width, depth_camera.height);
    test::fillImage(depth, [&](int u, int v) { return (u + v) % 2 == near_parity ? kNear_units : kFar_units; });
    Image<std::uint16_t> registered(colour_camera.width, colour_camera.height);
    registerDepthToColourCpu(depth.view(), registration, registered.view());
    for (int y = 0; y < colour_camera.height; ++y) {
      for (int x = 0; x < colour_camera.width; ++x) {
        ASSERT_EQ(registered(x, y), kNear_units) << x << "," << y << " near parity " << near_parity;
      }
    }
  }
}

// A box at 1 m in front of a wall at 3 m, colour camera 40 mm to the right: the box moves 2.8 px in
// the colour image, the wall 0.93 px, so the box covers the wall pixels beside it (they land on the
// same colour pixels) and uncovers wall the depth camera never saw, which stays a hole.
TEST(RegisterDepth, ABoxInFrontOfAWallHidesTheWallBehindIt) {
  const PinholeCamera camera = depthCamera();
  const DepthRegistration registration = sameIntrinsics(translation(0.04, 0.0, 0.0));
  constexpr int kBoxFirst = 30;
  constexpr int kBoxEnd = 50;  // box columns [30, 50), every row
  Image<std::uint16_t> depth(camera.width, camera.height);
  test::fillImage(depth, [&](int u, int) { return u >= kBoxFirst && u < kBoxEnd ? kNear_units : kFar_units; });
  Image<std::uint16_t> registered(camera.width, camera.height);
  registerDepthToColourCpu(depth.view(), registration, registered.view());
  // Box column u lands on u + 3: colour columns 33..52. Wall column u lands on u + 1: 1..30 and 51..79,
  // so colour columns 51 and 52 receive both wall and box; 31 and 32 receive nothing.
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      const std::uint16_t expected = x >= 33 && x <= 52 ? kNear_units : (x == 0 || x == 31 || x == 32 ? 0 : kFar_units);
      ASSERT_EQ(registered(x, y), expected) << x << "," << y;
    }
  }
}

// The colour camera 0.3 m to the side of a wall at 1 m: the depth image moves by 21 px, the right
// 21 columns fall outside the colour image and are dropped, the left 21 colour columns stay empty.
TEST(RegisterDepth, PointsOutsideTheColourViewAreDropped) {
  const PinholeCamera camera = depthCamera();
  Image<std::uint16_t> registered(camera.width, camera.height);
  registerDepthToColourCpu(constantDepth(camera, kNear_units).view(), sameIntrinsics(translation(0.3, 0.0, 0.0)),
                           registered.view());
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) ASSERT_EQ(registered(x, y), x < 21 ? 0 : kNear_units) << x << "," << y;
  }
}

TEST(RegisterDepth, PointsBehindTheColourCameraOrBeyondUint16AreDropped) {
  const PinholeCamera camera = depthCamera();
  Image<std::uint16_t> registered(camera.width, camera.height);
  // Turned around: everything is behind the colour camera.
  const SE3d turned(Eigen::Quaterniond(Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitY())),
                    Eigen::Vector3d::Zero());
  registerDepthToColourCpu(constantDepth(camera, kNear_units).view(), sameIntrinsics(turned), registered.view());
  EXPECT_EQ(countNonZero(registered), 0u);
  // 1 m farther along the axis: 60 m stays (61 000 units), 65 m would need 66 000 units.
  const DepthRegistration farther = sameIntrinsics(translation(0.0, 0.0, 1.0));
  registerDepthToColourCpu(constantDepth(camera, 60000).view(), farther, registered.view());
  EXPECT_EQ(registered(40, 30), 61000);
  registerDepthToColourCpu(constantDepth(camera, 65000).view(), farther, registered.view());
  EXPECT_EQ(countNonZero(registered), 0u);
}

TEST(RegisterDepth, BadCalibrationNamesTheField) {
  const auto expectError = [](DepthRegistration registration, const std::string& name) {
    Image<std::uint16_t> depth(80, 60), registered(80, 60);
    try {
      registerDepthToColourCpu(depth.view(), registration, registered.view());
      ADD_FAILURE() << "accepted a bad '" << name << "'";
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find("'" + name + "'"), std::string::npos) << error.what();
    }
  };
  DepthRegistration r = sameIntrinsics(translation(0.025, 0.0, 0.0));
  r.depth.fx = 0.0;
  expectError(r, "depth");
  r = sameIntrinsics(translation(0.025, 0.0, 0.0));
  r.colour.width = 0;
  expectError(r, "colour");
  r = sameIntrinsics(translation(25.0, 0.0, 0.0));  // millimetres given as metres
  expectError(r, "T_C_D");
  r = sameIntrinsics(translation(std::nan(""), 0.0, 0.0));
  expectError(r, "T_C_D");
  r = sameIntrinsics(translation(0.025, 0.0, 0.0));
  r.depth_scale_m = 0.0;
  expectError(r, "depth_scale_m");
  r.depth_scale_m = 1.0;  // metres per unit: a scale in the wrong unit
  expectError(r, "depth_scale_m");
}

TEST(RegisterDepth, MismatchedViewsAreRefused) {
  const DepthRegistration registration = sameIntrinsics(translation(0.025, 0.0, 0.0));
  Image<std::uint16_t> depth(80, 60), wrong(81, 60);
  EXPECT_THROW(registerDepthToColourCpu(wrong.view(), registration, depth.view()), std::invalid_argument);
  EXPECT_THROW(registerDepthToColourCpu(depth.view(), registration, wrong.view()), std::invalid_argument);
}

TEST(RegisterDepth, AllocatesNothingPerFrame) {
  const PinholeCamera depth_camera = PinholeCamera::create(480, 360, 340.0, 340.0, 239.5, 179.5);
  const PinholeCamera colour_camera = PinholeCamera::create(640, 480, 470.0, 470.0, 319.5, 239.5);
  const DepthRegistration registration{depth_camera, colour_camera, translation(-0.025, 0.0, 0.0), kDepthScale_m};
  Image<std::uint16_t> depth = constantDepth(depth_camera, 1500);
  Image<std::uint16_t> registered(colour_camera.width, colour_camera.height);
  const std::uint64_t before = vifusion::test::heapAllocationCount();
  for (int frame = 0; frame < 3; ++frame) registerDepthToColourCpu(depth.view(), registration, registered.view());
  EXPECT_EQ(vifusion::test::heapAllocationCount(), before);
  EXPECT_GT(countNonZero(registered), 100000u);
}

}  // namespace
}  // namespace vifusion::preprocess
