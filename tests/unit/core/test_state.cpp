#include <gtest/gtest.h>

#include <numbers>
#include <vector>

#include "vifusion/test/random_inputs.hpp"
#include "vifusion/core/numeric_diff.hpp"
#include "vifusion/core/so3.hpp"
#include "vifusion/core/state.hpp"
#include "vifusion/test/eigen_asserts.hpp"

namespace vifusion {
namespace {

using std::numbers::pi;

static_assert(kIdxR == 0 && kIdxAlpha == 3 && kIdxV == 6 && kIdxBg == 9 && kIdxBa == 12 && kIdxG == 15 &&
                  kStateDim == 18,
              "δx = [δr, δα, δv, δb_g, δb_a, δg], three entries each");

NavState randomState(test::RandomInputs& rnd) {
  NavState x;
  x.r_W_C = rnd.vector<3>(10.0);
  x.q_W_C = rnd.rotation();
  x.v_I_S = rnd.vector<3>(2.0);
  x.b_g = rnd.vector<3>(0.01);
  x.b_a = rnd.vector<3>(0.2);
  x.q_I_W = rnd.rotation();
  return x;
}

/// A perturbation whose rotation parts stay below `max_angle_rad`.
Vector18d randomDelta(test::RandomInputs& rnd, double max_angle_rad) {
  Vector18d d = rnd.vector<18>(1.0);
  d.segment<3>(kIdxAlpha) = rnd.rotationVector(max_angle_rad);
  d.segment<3>(kIdxG) = rnd.rotationVector(max_angle_rad);
  return d;
}

void expectStatesNear(const NavState& a, const NavState& b, double tol) {
  EXPECT_MATRIX_NEAR(a.r_W_C, b.r_W_C, tol);
  EXPECT_ROTATION_NEAR(a.q_W_C, b.q_W_C, tol);
  EXPECT_MATRIX_NEAR(a.v_I_S, b.v_I_S, tol);
  EXPECT_MATRIX_NEAR(a.b_g, b.b_g, tol);
  EXPECT_MATRIX_NEAR(a.b_a, b.b_a, tol);
  EXPECT_ROTATION_NEAR(a.q_I_W, b.q_I_W, tol);
}

TEST(NavState, DefaultIsZeroAndIdentity) {
  const NavState x;
  EXPECT_MATRIX_NEAR(x.r_W_C, Eigen::Vector3d::Zero(), 0.0);
  EXPECT_EQ(x.q_W_C.w(), 1.0);
  EXPECT_EQ(x.q_I_W.w(), 1.0);
  EXPECT_MATRIX_NEAR(boxMinus(x, x), Vector18d::Zero(), 0.0);
}

TEST(NavState, BoxPlusKnownValues) {
  NavState x;
  x.r_W_C = Eigen::Vector3d(1.0, 2.0, 3.0);
  x.q_W_C = expSO3(Eigen::Vector3d(pi / 2.0, 0.0, 0.0));  // quarter turn about x
  x.b_a = Eigen::Vector3d(0.1, 0.0, 0.0);

  Vector18d d = Vector18d::Zero();
  d.segment<3>(kIdxR) = Eigen::Vector3d(0.5, -1.0, 0.25);
  d.segment<3>(kIdxAlpha) = Eigen::Vector3d(0.0, 0.0, pi / 2.0);  // quarter turn about W's z
  d.segment<3>(kIdxV) = Eigen::Vector3d(1.0, 0.0, 0.0);
  d.segment<3>(kIdxBg) = Eigen::Vector3d(0.0, 0.001, 0.0);
  d.segment<3>(kIdxBa) = Eigen::Vector3d(0.0, 0.0, -0.05);
  d.segment<3>(kIdxG) = Eigen::Vector3d(0.01, 0.0, 0.0);
  const NavState y = boxPlus(x, d);

  EXPECT_MATRIX_NEAR(y.r_W_C, Eigen::Vector3d(1.5, 1.0, 3.25), 1e-15);
  EXPECT_MATRIX_NEAR(y.v_I_S, Eigen::Vector3d(1.0, 0.0, 0.0), 0.0);
  EXPECT_MATRIX_NEAR(y.b_g, Eigen::Vector3d(0.0, 0.001, 0.0), 0.0);
  EXPECT_MATRIX_NEAR(y.b_a, Eigen::Vector3d(0.1, 0.0, -0.05), 0.0);
  // Left perturbation: R_W_C' = R_z(90°)·R_x(90°). The camera's y axis goes to W's z (R_x), then stays
  // on z (R_z); its x axis stays on W's x, then turns to W's y. A right perturbation would differ.
  EXPECT_MATRIX_NEAR(y.q_W_C * Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ(), 1e-15);
  EXPECT_MATRIX_NEAR(y.q_W_C * Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), 1e-15);
  EXPECT_ROTATION_NEAR(y.q_I_W, expSO3(Eigen::Vector3d(0.01, 0.0, 0.0)), 1e-16);
  EXPECT_NEAR(y.q_W_C.norm(), 1.0, 1e-15);

  expectStatesNear(boxPlus(x, Vector18d::Zero()), x, 0.0);
}

TEST(NavState, BoxMinusIsSignInvariantAndAntisymmetric) {
  test::RandomInputs rnd(21);
  for (int i = 0; i < 100; ++i) {
    const NavState a = randomState(rnd);
    const NavState b = randomState(rnd);
    NavState a_flipped = a;
    a_flipped.q_W_C.coeffs() *= -1.0;
    a_flipped.q_I_W.coeffs() *= -1.0;
    EXPECT_MATRIX_NEAR(boxMinus(a_flipped, b), boxMinus(a, b), 1e-15);
    EXPECT_MATRIX_NEAR(boxMinus(b, a), -boxMinus(a, b), 1e-12);
  }
}

TEST(NavState, BoxPlusThenMinusRecoversDelta) {
  test::RandomInputs rnd(22);
  for (int i = 0; i < 1000; ++i) {
    const NavState x = randomState(rnd);
    const Vector18d d = randomDelta(rnd, pi - 1e-6);
    ASSERT_MATRIX_NEAR(boxMinus(boxPlus(x, d), x), d, 1e-11);
  }
  // Tiny and zero perturbations are recovered exactly enough for Gauss-Newton increments.
  const NavState x = randomState(rnd);
  for (const double scale : {0.0, 1e-12, 1e-9, 1e-6}) {
    const Vector18d d = scale * Vector18d::LinSpaced(1.0, 2.0);
    ASSERT_MATRIX_NEAR(boxMinus(boxPlus(x, d), x), d, 1e-15 + 1e-9 * scale);
  }
}

TEST(NavState, MinusThenPlusRecoversState) {
  test::RandomInputs rnd(23);
  for (int i = 0; i < 1000; ++i) {
    const NavState x = randomState(rnd);
    const NavState y = randomState(rnd);
    SCOPED_TRACE(::testing::Message() << "sample " << i);
    expectStatesNear(boxPlus(x, boxMinus(y, x)), y, 1e-12);
    if (HasFailure()) return;
  }
}

class BoxMinusJacobianTest : public ::testing::TestWithParam<int> {};

TEST_P(BoxMinusJacobianTest, JacobiansMatchNumeric) {
  test::RandomInputs rnd(100 + static_cast<unsigned>(GetParam()));
  const NavState b = randomState(rnd);
  // Differences from none over small to close to π (where a ⊟ b's rotations are largest).
  const double max_angle = std::vector<double>{0.0, 1e-6, 0.05, 1.0, 2.5, pi - 1e-3}[GetParam() % 6];
  Vector18d d = randomDelta(rnd, max_angle);
  if (max_angle == pi - 1e-3) {
    d.segment<3>(kIdxAlpha) = max_angle * rnd.unitVector();
    d.segment<3>(kIdxG) = max_angle * rnd.unitVector();
  }
  const NavState a = boxPlus(b, d);

  Matrix18d J_a;
  Matrix18d J_b;
  const Vector18d diff = boxMinus(a, b, &J_a, &J_b);
  const auto plus = [](const NavState& x, const Vector18d& delta) { return boxPlus(x, delta); };
  const Matrix18d J_a_num = numericJacobian<kStateDim>([&](const NavState& x) { return boxMinus(x, b); }, a, plus);
  const Matrix18d J_b_num = numericJacobian<kStateDim>([&](const NavState& x) { return boxMinus(a, x); }, b, plus);
  EXPECT_MATRIX_NEAR(J_a, J_a_num, 1e-6);
  EXPECT_MATRIX_NEAR(J_b, J_b_num, 1e-6);

  // Requesting one Jacobian or none gives the same values.
  Matrix18d J_a_only;
  EXPECT_MATRIX_NEAR(boxMinus(a, b, &J_a_only), diff, 0.0);
  EXPECT_MATRIX_NEAR(J_a_only, J_a, 0.0);
  Matrix18d J_b_only;
  EXPECT_MATRIX_NEAR(boxMinus(a, b, nullptr, &J_b_only), diff, 0.0);
  EXPECT_MATRIX_NEAR(J_b_only, J_b, 0.0);
}

INSTANTIATE_TEST_SUITE_P(Random, BoxMinusJacobianTest, ::testing::Range(0, 12));

TEST(NavState, BoxMinusJacobiansAtEqualStatesAreIdentity) {
  test::RandomInputs rnd(24);
  const NavState x = randomState(rnd);
  Matrix18d J_a;
  Matrix18d J_b;
  boxMinus(x, x, &J_a, &J_b);
  EXPECT_MATRIX_NEAR(J_a, Matrix18d::Identity(), 1e-15);
  EXPECT_MATRIX_NEAR(J_b, -Matrix18d::Identity(), 1e-15);
}

}  // namespace
}  // namespace vifusion
