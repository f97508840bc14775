#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <string>
#include <unsupported/Eigen/MatrixFunctions>
#include <vector>

#include "vifusion/test/random_inputs.hpp"
#include "vifusion/core/numeric_diff.hpp"
#include "vifusion/core/so3.hpp"
#include "vifusion/test/eigen_asserts.hpp"

namespace vifusion {
namespace {

using std::numbers::pi;

// Central differences with h = 1e-6 are good to ~1e-9; analytic-vs-numeric comparisons use 1e-7
// (1e-6 near θ = π where the inverse Jacobians grow).
constexpr double kJacobianTol = 1e-7;

/// Rotation vectors covering the special cases: zero, tiny, both sides of the series switch at 0.1 rad,
/// generic, and close to π.
std::vector<Eigen::Vector3d> edgeCaseRotationVectors() {
  const Eigen::Vector3d axis = Eigen::Vector3d(1.0, -2.0, 0.5).normalized();
  std::vector<Eigen::Vector3d> out;
  for (const double angle :
       {0.0, 1e-12, 1e-9, 1e-6, 1e-4, 0.01, 0.1 - 1e-9, 0.1, 0.1 + 1e-9, 0.5, 1.0, 2.0, 3.0, pi - 1e-3, pi - 1e-6}) {
    out.emplace_back(angle * axis);
  }
  return out;
}

TEST(So3, HatIsTheCrossProduct) {
  const Eigen::Vector3d a(1.0, -2.0, 3.0);
  const Eigen::Vector3d b(-0.5, 4.0, 2.0);
  EXPECT_MATRIX_NEAR(hat(a) * b, a.cross(b), 1e-15);
  EXPECT_MATRIX_NEAR(hat(a).transpose(), -hat(a), 0.0);
  Eigen::Matrix3d expected;
  expected << 0.0, -3.0, -2.0,  //
      3.0, 0.0, -1.0,           //
      2.0, 1.0, 0.0;
  EXPECT_MATRIX_NEAR(hat(a), expected, 0.0);
}

TEST(So3, ExpKnownValues) {
  const Eigen::Quaterniond q = expSO3(Eigen::Vector3d(0.0, 0.0, pi / 2.0));
  EXPECT_NEAR(q.w(), std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(q.x(), 0.0, 1e-15);
  EXPECT_NEAR(q.y(), 0.0, 1e-15);
  EXPECT_NEAR(q.z(), std::sqrt(0.5), 1e-15);
  // Active rotation: x-axis goes to y-axis.
  EXPECT_MATRIX_NEAR(q * Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), 1e-15);

  const Eigen::Quaterniond identity = expSO3(Eigen::Vector3d::Zero());
  EXPECT_EQ(identity.w(), 1.0);
  EXPECT_EQ(identity.vec(), Eigen::Vector3d::Zero());

  const Eigen::Quaterniond tiny = expSO3(Eigen::Vector3d(2e-9, 0.0, 0.0));
  EXPECT_NEAR(tiny.x(), 1e-9, 1e-24);
  EXPECT_NEAR(tiny.norm(), 1.0, 1e-16);
}

TEST(So3, HamiltonProductComposesLikeRotationMatrices) {
  test::RandomInputs rnd(1);
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d a = rnd.rotationVector(pi);
    const Eigen::Vector3d b = rnd.rotationVector(pi);
    const Eigen::Matrix3d R_a = Eigen::AngleAxisd(a.norm(), a.normalized()).toRotationMatrix();
    const Eigen::Matrix3d R_b = Eigen::AngleAxisd(b.norm(), b.normalized()).toRotationMatrix();
    EXPECT_MATRIX_NEAR((expSO3(a) * expSO3(b)).toRotationMatrix(), R_a * R_b, 1e-14);
    // And exp agrees with the matrix exponential of hat(a).
    EXPECT_MATRIX_NEAR(expSO3(a).toRotationMatrix(), hat(a).exp(), 1e-13);
  }
}

TEST(So3, LogInvertsExpForRandomAngles) {
  test::RandomInputs rnd(2);
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3d omega = rnd.rotationVector(pi - 1e-6);
    ASSERT_MATRIX_NEAR(logSO3(expSO3(omega)), omega, 1e-12);
    const Eigen::Quaterniond q = rnd.rotation();
    ASSERT_ROTATION_NEAR(expSO3(logSO3(q)), q, 1e-14);
  }
}

TEST(So3, LogInvertsExpAtEdgeCases) {
  for (const Eigen::Vector3d& omega : edgeCaseRotationVectors()) {
    // Near π the angle is recovered from w ≈ sin((π − θ)/2), so the absolute error stays ~1e-15 but
    // small angles must be recovered to relative precision.
    EXPECT_MATRIX_NEAR(logSO3(expSO3(omega)), omega, 1e-15 + 1e-14 * omega.norm()) << "|omega| = " << omega.norm();
  }
  // Below 1e-154 rad the squared norm underflows; the series branch still returns the exact value.
  const Eigen::Vector3d denormal_small(1e-160, -2e-160, 0.0);
  EXPECT_MATRIX_NEAR(logSO3(expSO3(denormal_small)) * 1e160, denormal_small * 1e160, 1e-15);
}

TEST(So3, LogAtAndBeyondPi) {
  const Eigen::Vector3d axis = Eigen::Vector3d(0.0, 0.6, 0.8);
  // Exactly π: either sign is the same rotation.
  const Eigen::Vector3d log_pi = logSO3(expSO3(pi * axis));
  EXPECT_NEAR(log_pi.norm(), pi, 1e-15);
  EXPECT_NEAR(std::abs(log_pi.dot(axis)), pi, 1e-15);
  EXPECT_ROTATION_NEAR(expSO3(log_pi), expSO3(pi * axis), 1e-15);
  // 1.5π about +axis is 0.5π about −axis.
  EXPECT_MATRIX_NEAR(logSO3(expSO3(1.5 * pi * axis)), -0.5 * pi * axis, 1e-14);
  // Just beyond π flips to just below π about −axis.
  EXPECT_MATRIX_NEAR(logSO3(expSO3((pi + 1e-7) * axis)), -(pi - 1e-7) * axis, 1e-14);
}

TEST(So3, LogIgnoresQuaternionSignAndScale) {
  test::RandomInputs rnd(3);
  for (int i = 0; i < 100; ++i) {
    const Eigen::Quaterniond q = rnd.rotation();
    const Eigen::Quaterniond minus_q(-q.w(), -q.x(), -q.y(), -q.z());
    const Eigen::Quaterniond scaled_q(1.001 * q.w(), 1.001 * q.x(), 1.001 * q.y(), 1.001 * q.z());
    EXPECT_MATRIX_NEAR(logSO3(minus_q), logSO3(q), 1e-15);
    EXPECT_MATRIX_NEAR(logSO3(scaled_q), logSO3(q), 1e-14);
    EXPECT_LE(logSO3(q).norm(), pi + 1e-15);
  }
  // Small angle with w < 0 (the −q representative of a small rotation).
  const Eigen::Quaterniond small = expSO3(Eigen::Vector3d(3e-9, 0.0, -4e-9));
  const Eigen::Quaterniond minus_small(-small.w(), -small.x(), -small.y(), -small.z());
  EXPECT_MATRIX_NEAR(logSO3(minus_small), Eigen::Vector3d(3e-9, 0.0, -4e-9), 1e-23);
}

TEST(So3, LeftJacobianKnownValue) {
  // φ = (0, 0, π/2): J_l = I + (1 − cos θ)/θ²·Φ + (θ − sin θ)/θ³·Φ² = [[2/π, −2/π, 0], [2/π, 2/π, 0], [0, 0, 1]].
  Eigen::Matrix3d expected;
  expected << 2.0 / pi, -2.0 / pi, 0.0,  //
      2.0 / pi, 2.0 / pi, 0.0,           //
      0.0, 0.0, 1.0;
  EXPECT_MATRIX_NEAR(leftJacobianSO3(Eigen::Vector3d(0.0, 0.0, pi / 2.0)), expected, 1e-15);
  EXPECT_MATRIX_NEAR(leftJacobianSO3(Eigen::Vector3d::Zero()), Eigen::Matrix3d::Identity(), 0.0);
  // Second order for tiny angles: J_l ≈ I + Φ/2 + Φ²/6, J_l⁻¹ ≈ I − Φ/2 + Φ²/12 (next terms ~1e-27).
  const Eigen::Vector3d tiny(1e-9, -2e-9, 3e-9);
  const Eigen::Matrix3d Phi = hat(tiny);
  EXPECT_MATRIX_NEAR(leftJacobianSO3(tiny), Eigen::Matrix3d::Identity() + Phi / 2.0 + Phi * Phi / 6.0, 1e-25);
  EXPECT_MATRIX_NEAR(leftJacobianInvSO3(tiny), Eigen::Matrix3d::Identity() - Phi / 2.0 + Phi * Phi / 12.0, 1e-25);
}

TEST(So3, JacobianIdentities) {
  std::vector<Eigen::Vector3d> inputs = edgeCaseRotationVectors();
  test::RandomInputs rnd(4);
  for (int i = 0; i < 100; ++i) inputs.push_back(rnd.rotationVector(pi - 1e-3));
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  for (const Eigen::Vector3d& phi : inputs) {
    SCOPED_TRACE(::testing::Message() << "|phi| = " << phi.norm());
    const Eigen::Matrix3d J_l = leftJacobianSO3(phi);
    const Eigen::Matrix3d J_r = rightJacobianSO3(phi);
    EXPECT_MATRIX_NEAR(J_r, leftJacobianSO3(-phi), 0.0);
    EXPECT_MATRIX_NEAR(J_r, J_l.transpose(), 1e-15);
    EXPECT_MATRIX_NEAR(J_l, expSO3(phi).toRotationMatrix() * J_r, 1e-14);
    // The inverses stay bounded for θ ≤ π (they diverge only towards 2π).
    EXPECT_MATRIX_NEAR(J_l * leftJacobianInvSO3(phi), I, 1e-14);
    EXPECT_MATRIX_NEAR(J_r * rightJacobianInvSO3(phi), I, 1e-14);
  }
}

TEST(So3, JacobiansAreContinuousAcrossTheSeriesSwitch) {
  const Eigen::Vector3d axis = Eigen::Vector3d(0.3, -0.4, 0.5).normalized();
  // Series and closed form meet at 0.1 rad (and 1e-4 rad for the non-cancelling ones): a wrong series
  // term would show as a jump of ~1e-8 or more; the true change over 2e-15 rad is ~1e-15.
  const Eigen::Vector3d below = (0.1 - 1e-15) * axis;
  const Eigen::Vector3d above = (0.1 + 1e-15) * axis;
  EXPECT_MATRIX_NEAR(leftJacobianSO3(below), leftJacobianSO3(above), 1e-14);
  EXPECT_MATRIX_NEAR(leftJacobianInvSO3(below), leftJacobianInvSO3(above), 1e-14);
  const Eigen::Vector3d tiny_below = (1e-4 - 1e-15) * axis;
  const Eigen::Vector3d tiny_above = (1e-4 + 1e-15) * axis;
  EXPECT_MATRIX_NEAR(leftJacobianSO3(tiny_below), leftJacobianSO3(tiny_above), 1e-15);
  EXPECT_ROTATION_NEAR(expSO3(tiny_below), expSO3(tiny_above), 2e-15 + 1e-16);  // they are 2e-15 rad apart
}

class So3JacobianTest : public ::testing::TestWithParam<Eigen::Vector3d> {};

TEST_P(So3JacobianTest, LeftJacobianMatchesNumeric) {
  const Eigen::Vector3d phi = GetParam();
  const Eigen::Quaterniond q_inv = expSO3(phi).conjugate();
  // exp(φ + δ) = exp(J_l·δ)·exp(φ)  ⇒  J_l = ∂ log(exp(x)·exp(φ)⁻¹)/∂x at x = φ.
  const auto f = [&](const Eigen::Vector3d& x) { return logSO3(expSO3(x) * q_inv); };
  EXPECT_MATRIX_NEAR(leftJacobianSO3(phi), numericJacobian(f, phi), kJacobianTol);
}

TEST_P(So3JacobianTest, RightJacobianMatchesNumeric) {
  const Eigen::Vector3d phi = GetParam();
  const Eigen::Quaterniond q_inv = expSO3(phi).conjugate();
  const auto f = [&](const Eigen::Vector3d& x) { return logSO3(q_inv * expSO3(x)); };
  EXPECT_MATRIX_NEAR(rightJacobianSO3(phi), numericJacobian(f, phi), kJacobianTol);
}

TEST_P(So3JacobianTest, LeftJacobianInverseMatchesNumeric) {
  const Eigen::Vector3d phi = GetParam();
  const auto log_of = [](const Eigen::Quaterniond& q) { return logSO3(q); };
  const auto plus_left = [](const Eigen::Quaterniond& q, const Eigen::Vector3d& d) { return expSO3(d) * q; };
  const Eigen::Matrix3d J_inv = leftJacobianInvSO3(phi);
  EXPECT_MATRIX_NEAR(J_inv, numericJacobian<3>(log_of, expSO3(phi), plus_left), kJacobianTol * (1.0 + J_inv.norm()));
}

TEST_P(So3JacobianTest, RightJacobianInverseMatchesNumeric) {
  const Eigen::Vector3d phi = GetParam();
  const auto log_of = [](const Eigen::Quaterniond& q) { return logSO3(q); };
  const auto plus_right = [](const Eigen::Quaterniond& q, const Eigen::Vector3d& d) { return q * expSO3(d); };
  const Eigen::Matrix3d J_inv = rightJacobianInvSO3(phi);
  EXPECT_MATRIX_NEAR(J_inv, numericJacobian<3>(log_of, expSO3(phi), plus_right), kJacobianTol * (1.0 + J_inv.norm()));
}

std::vector<Eigen::Vector3d> jacobianInputs() {
  std::vector<Eigen::Vector3d> inputs = edgeCaseRotationVectors();
  // The numeric inverse Jacobians perturb by 1e-6 and must not cross θ = π.
  inputs.pop_back();
  test::RandomInputs rnd(5);
  for (int i = 0; i < 20; ++i) inputs.push_back(rnd.rotationVector(pi - 1e-3));
  return inputs;
}

// Named by index: the printed vectors make unreadable test names (a failure still prints the value).
INSTANTIATE_TEST_SUITE_P(EdgeAndRandom, So3JacobianTest, ::testing::ValuesIn(jacobianInputs()),
                         [](const auto& info) { return "input" + std::to_string(info.index); });

}  // namespace
}  // namespace vifusion
