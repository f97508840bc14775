#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>
#include <string>

#include "vifusion/test/random_inputs.hpp"
#include "vifusion/core/numeric_diff.hpp"
#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/test/eigen_asserts.hpp"

namespace vifusion {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// TUM fr1-like default intrinsics and ICL-NUIM's (negative fy flips the rows).
PinholeCamera tumCamera() { return PinholeCamera::create(640, 480, 525.0, 525.0, 319.5, 239.5); }
PinholeCamera iclCamera() { return PinholeCamera::create(640, 480, 481.2, -480.0, 319.5, 239.5); }

TEST(PinholeCamera, CreateKeepsParameters) {
  const PinholeCamera cam = iclCamera();
  EXPECT_EQ(cam.width, 640);
  EXPECT_EQ(cam.height, 480);
  EXPECT_EQ(cam.fx, 481.2);
  EXPECT_EQ(cam.fy, -480.0);
  EXPECT_EQ(cam.cx, 319.5);
  EXPECT_EQ(cam.cy, 239.5);
}

/// create() must throw std::invalid_argument whose message contains `expected` ("name = value").
template <class Create>
void expectRejected(const Create& create, const std::string& expected) {
  try {
    create();
    ADD_FAILURE() << "accepted although " << expected;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << "message: " << e.what();
  }
}

TEST(PinholeCamera, CreateRejectsEachBadParameterByName) {
  expectRejected([] { return PinholeCamera::create(0, 480, 525, 525, 319.5, 239.5); }, "width = 0");
  expectRejected([] { return PinholeCamera::create(-640, 480, 525, 525, 319.5, 239.5); }, "width = -640");
  expectRejected([] { return PinholeCamera::create(640, 0, 525, 525, 319.5, 239.5); }, "height = 0");
  expectRejected([] { return PinholeCamera::create(640, -1, 525, 525, 319.5, 239.5); }, "height = -1");
  expectRejected([] { return PinholeCamera::create(640, 480, 0.0, 525, 319.5, 239.5); }, "fx = 0");
  expectRejected([] { return PinholeCamera::create(640, 480, -525.0, 525, 319.5, 239.5); }, "fx = -525");
  expectRejected([] { return PinholeCamera::create(640, 480, kNaN, 525, 319.5, 239.5); }, "fx = nan");
  expectRejected([] { return PinholeCamera::create(640, 480, kInf, 525, 319.5, 239.5); }, "fx = inf");
  expectRejected([] { return PinholeCamera::create(640, 480, 525, 0.0, 319.5, 239.5); }, "fy = 0");
  expectRejected([] { return PinholeCamera::create(640, 480, 525, kNaN, 319.5, 239.5); }, "fy = nan");
  expectRejected([] { return PinholeCamera::create(640, 480, 525, -kInf, 319.5, 239.5); }, "fy = -inf");
  expectRejected([] { return PinholeCamera::create(640, 480, 525, 525, kNaN, 239.5); }, "cx = nan");
  expectRejected([] { return PinholeCamera::create(640, 480, 525, 525, kInf, 239.5); }, "cx = inf");
  expectRejected([] { return PinholeCamera::create(640, 480, 525, 525, 319.5, kNaN); }, "cy = nan");
  expectRejected([] { return PinholeCamera::create(640, 480, 525, 525, 319.5, -kInf); }, "cy = -inf");
  // Negative fy and principal points outside the image are legitimate.
  EXPECT_NO_THROW(PinholeCamera::create(640, 480, 525, -525, -10.0, 900.0));
}

TEST(PinholeCamera, ProjectKnownPoints) {
  const Eigen::Vector3d p_C(0.1, -0.2, 2.0);
  EXPECT_MATRIX_NEAR(tumCamera().project(p_C), Eigen::Vector2d(345.75, 187.0), 1e-12);
  // ICL-NUIM: a point above the axis (y < 0) lands below the centre row because fy < 0.
  EXPECT_MATRIX_NEAR(iclCamera().project(p_C), Eigen::Vector2d(343.56, 287.5), 1e-12);
  EXPECT_MATRIX_NEAR(tumCamera().project(Eigen::Vector3d(0.0, 0.0, 5.0)), Eigen::Vector2d(319.5, 239.5), 0.0);
}

TEST(PinholeCamera, BackProjectKnownPixels) {
  EXPECT_MATRIX_NEAR(tumCamera().backProject(Eigen::Vector2d(345.75, 187.0), 2.0), Eigen::Vector3d(0.1, -0.2, 2.0),
                     1e-12);
  EXPECT_MATRIX_NEAR(iclCamera().backProject(Eigen::Vector2d(343.56, 287.5), 2.0), Eigen::Vector3d(0.1, -0.2, 2.0),
                     1e-12);
}

TEST(PinholeCamera, ProjectBackProjectRoundTrip) {
  test::RandomInputs rnd(31);
  for (const PinholeCamera& cam : {tumCamera(), iclCamera(), tumCamera().atLevel(2), iclCamera().atLevel(1)}) {
    for (int i = 0; i < 200; ++i) {
      const Eigen::Vector3d p_C(rnd.uniform(-2.0, 2.0), rnd.uniform(-1.5, 1.5), rnd.uniform(0.3, 8.0));
      ASSERT_MATRIX_NEAR(cam.backProject(cam.project(p_C), p_C.z()), p_C, 1e-12);
      const Eigen::Vector2d uv(rnd.uniform(0.0, cam.width - 1.0), rnd.uniform(0.0, cam.height - 1.0));
      const double z_m = rnd.uniform(0.3, 8.0);
      ASSERT_MATRIX_NEAR(cam.project(cam.backProject(uv, z_m)), uv, 1e-10);
    }
  }
}

TEST(PinholeCamera, ProjectionJacobianMatchesNumeric) {
  test::RandomInputs rnd(32);
  for (const PinholeCamera& cam : {tumCamera(), iclCamera()}) {
    for (int i = 0; i < 50; ++i) {
      const Eigen::Vector3d p_C(rnd.uniform(-2.0, 2.0), rnd.uniform(-1.5, 1.5), rnd.uniform(0.3, 8.0));
      Eigen::Matrix<double, 2, 3> J;
      const Eigen::Vector2d uv = cam.project(p_C, &J);
      EXPECT_MATRIX_NEAR(uv, cam.project(p_C), 0.0);
      const auto f = [&](const Eigen::Vector3d& p) { return cam.project(p); };
      // Entries reach fx/z ≈ 1750 px/m; central differences are good to ~1e-9 relative.
      EXPECT_MATRIX_NEAR(J, numericJacobian(f, p_C), 1e-5);
    }
  }
  // Known value at p = (0.1, −0.2, 2) for ICL-NUIM.
  Eigen::Matrix<double, 2, 3> J;
  iclCamera().project(Eigen::Vector3d(0.1, -0.2, 2.0), &J);
  Eigen::Matrix<double, 2, 3> expected;
  expected << 240.6, 0.0, -12.03,  //
      0.0, -240.0, -24.0;
  EXPECT_MATRIX_NEAR(J, expected, 1e-12);
}

TEST(PinholeCamera, AtLevelHalvesFocalLengthsAndPrincipalPoint) {
  const PinholeCamera l0 = iclCamera();
  EXPECT_EQ(l0.atLevel(0).fx, l0.fx);
  EXPECT_EQ(l0.atLevel(0).cx, l0.cx);
  const PinholeCamera l1 = l0.atLevel(1);
  EXPECT_EQ(l1.width, 320);
  EXPECT_EQ(l1.height, 240);
  EXPECT_DOUBLE_EQ(l1.fx, 240.6);
  EXPECT_DOUBLE_EQ(l1.fy, -240.0);
  EXPECT_DOUBLE_EQ(l1.cx, 159.75);
  EXPECT_DOUBLE_EQ(l1.cy, 119.75);
  const PinholeCamera l2 = l0.atLevel(2);
  EXPECT_EQ(l2.width, 160);
  EXPECT_EQ(l2.height, 120);
  EXPECT_DOUBLE_EQ(l2.fx, 120.3);
  EXPECT_DOUBLE_EQ(l2.cx, 79.875);
  EXPECT_DOUBLE_EQ(l2.cy, 59.875);
  // Odd sizes round down.
  const PinholeCamera odd = PinholeCamera::create(641, 481, 500, 500, 320.0, 240.0).atLevel(1);
  EXPECT_EQ(odd.width, 320);
  EXPECT_EQ(odd.height, 240);
  EXPECT_DOUBLE_EQ(odd.cx, 160.0);

  // A 3-D point projects to the level-l coordinate whose sample is centred on it: u_l = u_0 / 2^l.
  const Eigen::Vector3d p_C(0.3, 0.2, 1.7);
  const Eigen::Vector2d uv0 = l0.project(p_C);
  EXPECT_MATRIX_NEAR(l2.project(p_C), (uv0 / 4.0).eval(), 1e-12);
}

TEST(PinholeCamera, AtLevelRejectsImpossibleLevels) {
  const PinholeCamera cam = tumCamera();
  expectRejected([&] { return cam.atLevel(-1); }, "level = -1");
  expectRejected([&] { return cam.atLevel(9); }, "level = 9");  // 480 >> 9 = 0 rows
  expectRejected([&] { return cam.atLevel(40); }, "level = 40");
  EXPECT_EQ(cam.atLevel(8).height, 1);
}

TEST(PinholeCamera, IsInsideUsesPixelCentres) {
  const PinholeCamera cam = tumCamera();
  EXPECT_TRUE(cam.isInside({0.0, 0.0}));
  EXPECT_TRUE(cam.isInside({639.0, 479.0}));
  EXPECT_FALSE(cam.isInside({639.001, 100.0}));
  EXPECT_FALSE(cam.isInside({-0.001, 100.0}));
  EXPECT_FALSE(cam.isInside({100.0, 479.001}));
  EXPECT_FALSE(cam.isInside({100.0, -0.001}));
  EXPECT_TRUE(cam.isInside({2.0, 100.0}, 2.0));
  EXPECT_FALSE(cam.isInside({1.999, 100.0}, 2.0));
  EXPECT_TRUE(cam.isInside({637.0, 477.0}, 2.0));
  EXPECT_FALSE(cam.isInside({637.001, 100.0}, 2.0));
  EXPECT_FALSE(cam.isInside({100.0, 477.001}, 2.0));
  EXPECT_FALSE(cam.isInside({kNaN, 100.0}));
  EXPECT_FALSE(cam.isInside({100.0, kNaN}));
}

}  // namespace
}  // namespace vifusion
