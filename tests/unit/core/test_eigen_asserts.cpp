#include <gtest/gtest.h>

#include <Eigen/Core>
#include <limits>
#include <string>

#include "vifusion/core/so3.hpp"
#include "vifusion/test/eigen_asserts.hpp"

namespace vifusion::test {
namespace {

TEST(EigenAsserts, PassesWithinTolerance) {
  Eigen::Matrix2d a;
  a << 1.0, 2.0, 3.0, 4.0;
  const Eigen::Matrix2d b = a + Eigen::Matrix2d::Constant(0.5e-6);
  EXPECT_TRUE(matricesNear(a, b, 1e-6));
  EXPECT_MATRIX_NEAR(a, b, 1e-6);
  EXPECT_MATRIX_NEAR(Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(1, 2, 3), 0.0);
}

TEST(EigenAsserts, FailureNamesLocationAndPrintsBothMatrices) {
  Eigen::Matrix<double, 2, 3> a = Eigen::Matrix<double, 2, 3>::Zero();
  Eigen::Matrix<double, 2, 3> b = a;
  b(1, 2) = 0.25;
  b(0, 0) = 0.125;
  const ::testing::AssertionResult result = matricesNearFormat("J_analytic", "J_numeric", "tol", a, b, 1e-3);
  ASSERT_FALSE(result);
  const std::string message = result.message();
  EXPECT_NE(message.find("J_analytic and J_numeric differ by 0.25 at (1, 2), tolerance 0.001"), std::string::npos)
      << message;
  // Both matrices follow, columns aligned, full precision.
  EXPECT_NE(message.find("J_analytic =\n  [0, 0, 0]\n  [0, 0, 0]\n"), std::string::npos) << message;
  EXPECT_NE(message.find("J_numeric =\n  [0.125,     0,     0]\n  [    0,     0,  0.25]\n"), std::string::npos)
      << message;
  EXPECT_NE(message.find("difference ="), std::string::npos) << message;
}

TEST(EigenAsserts, SizeMismatchAndNonFiniteFail) {
  EXPECT_FALSE(matricesNear(Eigen::Vector3d::Zero(), Eigen::Vector2d::Zero(), 1.0));
  Eigen::Vector2d nan_vector(0.0, std::numeric_limits<double>::quiet_NaN());
  EXPECT_FALSE(matricesNear(nan_vector, nan_vector, 1.0));
  const Eigen::Vector2d inf_vector(std::numeric_limits<double>::infinity(), 0.0);
  EXPECT_FALSE(matricesNear(inf_vector, inf_vector, 1.0));
}

TEST(EigenAsserts, RotationsCompareBySignFreeAngle) {
  const Eigen::Quaterniond q = expSO3(Eigen::Vector3d(0.3, -0.2, 0.1));
  const Eigen::Quaterniond minus_q(-q.w(), -q.x(), -q.y(), -q.z());
  EXPECT_ROTATION_NEAR(q, minus_q, 1e-12);
  const Eigen::Quaterniond q_off = expSO3(Eigen::Vector3d(0.0, 0.0, 1e-3)) * q;
  EXPECT_TRUE(rotationsNearFormat("a", "b", "tol", q, q_off, 1.001e-3));
  EXPECT_FALSE(rotationsNearFormat("a", "b", "tol", q, q_off, 0.999e-3));
}

}  // namespace
}  // namespace vifusion::test
