#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <unsupported/Eigen/MatrixFunctions>
#include <vector>

#include "vifusion/test/random_inputs.hpp"
#include "vifusion/core/numeric_diff.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/core/so3.hpp"
#include "vifusion/test/eigen_asserts.hpp"

namespace vifusion {
namespace {

using std::numbers::pi;

constexpr double kJacobianTol = 1e-7;  // central differences with h = 1e-6 are good to ~1e-9

/// 4×4 twist matrix ξ^ = [hat(φ) ρ; 0 0] for ξ = [ρ; φ].
Eigen::Matrix4d twistMatrix(const Vector6d& xi) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  m.topLeftCorner<3, 3>() = hat(xi.tail<3>());
  m.topRightCorner<3, 1>() = xi.head<3>();
  return m;
}

Vector6d twist(const Eigen::Vector3d& rho, const Eigen::Vector3d& phi) {
  Vector6d xi;
  xi << rho, phi;
  return xi;
}

SE3d randomPose(test::RandomInputs& rnd) { return SE3d(rnd.rotation(), rnd.vector<3>(5.0)); }

/// Twists with the rotation angle at the special cases and a translation of a few metres.
std::vector<Vector6d> edgeCaseTwists() {
  const Eigen::Vector3d axis = Eigen::Vector3d(-0.3, 0.5, 0.8).normalized();
  const Eigen::Vector3d rho(1.5, -0.7, 2.0);
  std::vector<Vector6d> out;
  for (const double angle :
       {0.0, 1e-12, 1e-9, 1e-6, 1e-4, 0.01, 0.1 - 1e-9, 0.1, 0.1 + 1e-9, 0.5, 1.0, 2.0, 3.0, pi - 1e-3}) {
    out.push_back(twist(rho, angle * axis));
  }
  out.push_back(twist(Eigen::Vector3d::Zero(), 0.7 * axis));
  return out;
}

TEST(Se3, DefaultIsIdentityAndConstructorNormalises) {
  const SE3d identity;
  EXPECT_MATRIX_NEAR(identity.matrix(), Eigen::Matrix4d::Identity(), 0.0);
  const SE3d T(Eigen::Quaterniond(2.0, 0.0, 0.0, 0.0), Eigen::Vector3d(1.0, 2.0, 3.0));
  EXPECT_DOUBLE_EQ(T.quaternion().w(), 1.0);
  EXPECT_MATRIX_NEAR(T.translation(), Eigen::Vector3d(1.0, 2.0, 3.0), 0.0);
}

TEST(Se3, ActsOnPointsAsRotationThenTranslation) {
  // T_a_b: rotate 90° about z, then translate by (1, 2, 3).
  const SE3d T_a_b(expSO3(Eigen::Vector3d(0.0, 0.0, pi / 2.0)), Eigen::Vector3d(1.0, 2.0, 3.0));
  EXPECT_MATRIX_NEAR(T_a_b * Eigen::Vector3d(1.0, 0.0, 0.0), Eigen::Vector3d(1.0, 3.0, 3.0), 1e-15);
  EXPECT_MATRIX_NEAR(T_a_b.inverse() * Eigen::Vector3d(1.0, 3.0, 3.0), Eigen::Vector3d(1.0, 0.0, 0.0), 1e-15);
  Eigen::Matrix4d expected;
  expected << 0.0, -1.0, 0.0, 1.0,  //
      1.0, 0.0, 0.0, 2.0,           //
      0.0, 0.0, 1.0, 3.0,           //
      0.0, 0.0, 0.0, 1.0;
  EXPECT_MATRIX_NEAR(T_a_b.matrix(), expected, 1e-15);
}

TEST(Se3, ComposeAndInverseMatchMatrices) {
  test::RandomInputs rnd(11);
  for (int i = 0; i < 100; ++i) {
    const SE3d T_a_b = randomPose(rnd);
    const SE3d T_b_c = randomPose(rnd);
    const Eigen::Vector3d p_c = rnd.vector<3>(3.0);
    EXPECT_MATRIX_NEAR((T_a_b * T_b_c).matrix(), T_a_b.matrix() * T_b_c.matrix(), 1e-13);
    EXPECT_MATRIX_NEAR((T_a_b * T_b_c) * p_c, T_a_b * (T_b_c * p_c), 1e-13);
    EXPECT_MATRIX_NEAR(T_a_b.inverse().matrix(), T_a_b.matrix().inverse(), 1e-13);
    EXPECT_MATRIX_NEAR((T_a_b * T_a_b.inverse()).matrix(), Eigen::Matrix4d::Identity(), 1e-14);
    EXPECT_NEAR((T_a_b * T_b_c).quaternion().norm(), 1.0, 1e-15);
  }
}

TEST(Se3, ExpKnownValues) {
  // Pure translation.
  const SE3d T_t = SE3d::exp(twist(Eigen::Vector3d(1.0, 2.0, 3.0), Eigen::Vector3d::Zero()));
  EXPECT_MATRIX_NEAR(T_t.translation(), Eigen::Vector3d(1.0, 2.0, 3.0), 0.0);
  EXPECT_ROTATION_NEAR(T_t.quaternion(), Eigen::Quaterniond::Identity(), 0.0);
  // ρ = (1, 0, 0) along a quarter turn about z moves along the arc: t = J_l(φ)·ρ = (2/π, 2/π, 0).
  const SE3d T_r = SE3d::exp(twist(Eigen::Vector3d(1.0, 0.0, 0.0), Eigen::Vector3d(0.0, 0.0, pi / 2.0)));
  EXPECT_MATRIX_NEAR(T_r.translation(), Eigen::Vector3d(2.0 / pi, 2.0 / pi, 0.0), 1e-15);
  EXPECT_MATRIX_NEAR(T_r * Eigen::Vector3d::UnitX(), Eigen::Vector3d(2.0 / pi, 1.0 + 2.0 / pi, 0.0), 1e-15);
}

TEST(Se3, ExpMatchesMatrixExponential) {
  test::RandomInputs rnd(12);
  std::vector<Vector6d> inputs = edgeCaseTwists();
  for (int i = 0; i < 50; ++i) inputs.push_back(twist(rnd.vector<3>(3.0), rnd.rotationVector(pi)));
  for (const Vector6d& xi : inputs) {
    EXPECT_MATRIX_NEAR(SE3d::exp(xi).matrix(), twistMatrix(xi).exp(), 1e-12) << "xi = " << xi.transpose();
  }
}

TEST(Se3, LogInvertsExp) {
  test::RandomInputs rnd(13);
  std::vector<Vector6d> inputs = edgeCaseTwists();
  for (int i = 0; i < 1000; ++i) inputs.push_back(twist(rnd.vector<3>(3.0), rnd.rotationVector(pi - 1e-6)));
  for (const Vector6d& xi : inputs) {
    ASSERT_MATRIX_NEAR(SE3d::exp(xi).log(), xi, 1e-11) << "xi = " << xi.transpose();
  }
  for (int i = 0; i < 100; ++i) {
    const SE3d T = randomPose(rnd);
    ASSERT_MATRIX_NEAR(SE3d::exp(T.log()).matrix(), T.matrix(), 1e-12);
  }
  // A half turn: log may return either axis sign but exp(log(T)) is T.
  const SE3d T_pi(expSO3(pi * Eigen::Vector3d::UnitY()), Eigen::Vector3d(0.5, -1.0, 2.0));
  EXPECT_NEAR(T_pi.log().tail<3>().norm(), pi, 1e-15);
  EXPECT_MATRIX_NEAR(SE3d::exp(T_pi.log()).matrix(), T_pi.matrix(), 1e-12);
}

TEST(Se3, AdjointProperties) {
  test::RandomInputs rnd(14);
  for (int i = 0; i < 20; ++i) {
    const SE3d T = randomPose(rnd);
    const SE3d U = randomPose(rnd);
    const Vector6d xi = twist(rnd.vector<3>(1.0), rnd.rotationVector(2.0));
    // T·exp(ξ)·T⁻¹ = exp(Ad(T)·ξ) exactly, not only to first order.
    EXPECT_MATRIX_NEAR((T * SE3d::exp(xi) * T.inverse()).matrix(), SE3d::exp(T.adjoint() * xi).matrix(), 1e-12);
    EXPECT_MATRIX_NEAR((T * U).adjoint(), T.adjoint() * U.adjoint(), 1e-12);
    EXPECT_MATRIX_NEAR(T.inverse().adjoint(), T.adjoint().inverse(), 1e-12);
  }
}

TEST(Se3, JacobianIdentities) {
  test::RandomInputs rnd(15);
  std::vector<Vector6d> inputs = edgeCaseTwists();
  for (int i = 0; i < 50; ++i) inputs.push_back(twist(rnd.vector<3>(3.0), rnd.rotationVector(pi - 1e-3)));
  for (const Vector6d& xi : inputs) {
    SCOPED_TRACE(::testing::Message() << "xi = " << xi.transpose());
    const Matrix6d J_l = SE3d::leftJacobian(xi);
    const Matrix6d J_r = SE3d::rightJacobian(xi);
    EXPECT_MATRIX_NEAR(J_l, SE3d::exp(xi).adjoint() * J_r, 1e-13);
    EXPECT_MATRIX_NEAR(J_l * SE3d::leftJacobianInv(xi), Matrix6d::Identity(), 1e-13);
    EXPECT_MATRIX_NEAR(J_r * SE3d::rightJacobianInv(xi), Matrix6d::Identity(), 1e-13);
    // The rotation blocks are the SO(3) Jacobians.
    const Eigen::Matrix3d J_so3 = leftJacobianSO3(xi.tail<3>());
    EXPECT_MATRIX_NEAR(J_l.topLeftCorner(3, 3), J_so3, 0.0);
    EXPECT_MATRIX_NEAR(J_l.bottomRightCorner(3, 3), J_so3, 0.0);
    EXPECT_MATRIX_NEAR(J_l.bottomLeftCorner(3, 3), Eigen::Matrix3d::Zero(), 0.0);
  }
  // Q(ρ, φ) is continuous across the series switch at |φ| = 0.1 rad.
  const Eigen::Vector3d axis = Eigen::Vector3d(0.3, -0.4, 0.5).normalized();
  const Eigen::Vector3d rho(2.0, 1.0, -3.0);
  EXPECT_MATRIX_NEAR(SE3d::leftJacobian(twist(rho, (0.1 - 1e-15) * axis)),
                     SE3d::leftJacobian(twist(rho, (0.1 + 1e-15) * axis)), 1e-13);
}

class Se3JacobianTest : public ::testing::TestWithParam<Vector6d> {};

const auto kPlusLeft = [](const SE3d& T, const Vector6d& d) { return SE3d::exp(d) * T; };
const auto kPlusRight = [](const SE3d& T, const Vector6d& d) { return T * SE3d::exp(d); };
const auto kLogOf = [](const SE3d& T) { return T.log(); };

TEST_P(Se3JacobianTest, LeftJacobianMatchesNumeric) {
  const Vector6d xi = GetParam();
  const SE3d T_inv = SE3d::exp(xi).inverse();
  const auto f = [&](const Vector6d& x) { return (SE3d::exp(x) * T_inv).log(); };
  EXPECT_MATRIX_NEAR(SE3d::leftJacobian(xi), numericJacobian(f, xi), kJacobianTol);
}

TEST_P(Se3JacobianTest, RightJacobianMatchesNumeric) {
  const Vector6d xi = GetParam();
  const SE3d T_inv = SE3d::exp(xi).inverse();
  const auto f = [&](const Vector6d& x) { return (T_inv * SE3d::exp(x)).log(); };
  EXPECT_MATRIX_NEAR(SE3d::rightJacobian(xi), numericJacobian(f, xi), kJacobianTol);
}

TEST_P(Se3JacobianTest, LeftJacobianInverseMatchesNumeric) {
  const Vector6d xi = GetParam();
  EXPECT_MATRIX_NEAR(SE3d::leftJacobianInv(xi), numericJacobian<6>(kLogOf, SE3d::exp(xi), kPlusLeft), kJacobianTol);
}

TEST_P(Se3JacobianTest, RightJacobianInverseMatchesNumeric) {
  const Vector6d xi = GetParam();
  EXPECT_MATRIX_NEAR(SE3d::rightJacobianInv(xi), numericJacobian<6>(kLogOf, SE3d::exp(xi), kPlusRight), kJacobianTol);
}

TEST_P(Se3JacobianTest, AdjointMatchesNumeric) {
  const SE3d T = SE3d::exp(GetParam());
  const auto f = [&](const Vector6d& d) { return (T * SE3d::exp(d) * T.inverse()).log(); };
  EXPECT_MATRIX_NEAR(T.adjoint(), numericJacobian(f, Vector6d::Zero().eval()), kJacobianTol);
}

TEST_P(Se3JacobianTest, PointJacobiansMatchNumeric) {
  const SE3d T_a_b = SE3d::exp(GetParam());
  const Eigen::Vector3d p_b(0.4, -1.2, 2.5);
  const auto transform = [&](const SE3d& T) { return T * p_b; };
  EXPECT_MATRIX_NEAR(T_a_b.pointJacobianLeft(p_b), numericJacobian<6>(transform, T_a_b, kPlusLeft), kJacobianTol);
  EXPECT_MATRIX_NEAR(T_a_b.pointJacobianRight(p_b), numericJacobian<6>(transform, T_a_b, kPlusRight), kJacobianTol);
}

std::vector<Vector6d> jacobianInputs() {
  std::vector<Vector6d> inputs = edgeCaseTwists();
  test::RandomInputs rnd(16);
  for (int i = 0; i < 20; ++i) inputs.push_back(twist(rnd.vector<3>(3.0), rnd.rotationVector(pi - 1e-3)));
  return inputs;
}

// Named by index: the printed vectors make unreadable test names (a failure still prints the value).
INSTANTIATE_TEST_SUITE_P(EdgeAndRandom, Se3JacobianTest, ::testing::ValuesIn(jacobianInputs()),
                         [](const auto& info) { return "input" + std::to_string(info.index); });

}  // namespace
}  // namespace vifusion
