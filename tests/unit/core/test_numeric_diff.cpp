#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <type_traits>

#include "vifusion/core/numeric_diff.hpp"
#include "vifusion/core/so3.hpp"
#include "vifusion/test/eigen_asserts.hpp"

namespace vifusion {
namespace {

TEST(NumericDiff, LinearMapIsRecoveredExactlyEnough) {
  Eigen::Matrix<double, 2, 3> A;
  A << 1.0, -2.0, 0.5,  //
      3.0, 0.25, -4.0;
  const auto f = [&](const Eigen::Vector3d& x) -> Eigen::Vector2d { return A * x; };
  const auto J = numericJacobian(f, Eigen::Vector3d(0.3, -1.0, 2.0));
  static_assert(std::is_same_v<std::decay_t<decltype(J)>, Eigen::Matrix<double, 2, 3>>, "fixed-size result");
  EXPECT_MATRIX_NEAR(J, A, 1e-9);
}

TEST(NumericDiff, NonlinearFunctionMatchesClosedForm) {
  // f(x) = [sin(x0)·x1, x2², exp(x0 − x2)]
  const auto f = [](const Eigen::Vector3d& x) {
    return Eigen::Vector3d(std::sin(x[0]) * x[1], x[2] * x[2], std::exp(x[0] - x[2]));
  };
  const Eigen::Vector3d x(0.7, -1.3, 0.4);
  Eigen::Matrix3d J_expected;
  J_expected << std::cos(0.7) * -1.3, std::sin(0.7), 0.0,  //
      0.0, 0.0, 0.8,                                       //
      std::exp(0.3), 0.0, -std::exp(0.3);
  EXPECT_MATRIX_NEAR(numericJacobian(f, x), J_expected, 1e-8);
  // A coarser step is visibly worse (O(h²) truncation), which shows the step is honoured.
  const double coarse_error = (numericJacobian(f, x, 1e-2) - J_expected).cwiseAbs().maxCoeff();
  EXPECT_GT(coarse_error, 1e-7);
  EXPECT_LT(coarse_error, 1e-4);
}

TEST(NumericDiff, DynamicSizesWork) {
  const auto f = [](const Eigen::VectorXd& x) {
    Eigen::VectorXd y(2);
    y << x.sum(), x.squaredNorm();
    return y;
  };
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(4, 1.0, 4.0);
  const Eigen::MatrixXd J = numericJacobian(f, x);
  ASSERT_EQ(J.rows(), 2);
  ASSERT_EQ(J.cols(), 4);
  Eigen::MatrixXd J_expected(2, 4);
  J_expected << 1.0, 1.0, 1.0, 1.0,  //
      2.0, 4.0, 6.0, 8.0;
  EXPECT_MATRIX_NEAR(J, J_expected, 1e-8);
}

TEST(NumericDiff, ManifoldInputWithLeftPerturbation) {
  // f(q) = q·p; perturbing q on the left by exp(δ): ∂(exp(δ)·q·p)/∂δ = −hat(q·p).
  const Eigen::Vector3d p(1.0, -2.0, 0.5);
  const Eigen::Quaterniond q = expSO3(Eigen::Vector3d(0.4, 0.1, -0.9));
  const auto rotate = [&](const Eigen::Quaterniond& r) -> Eigen::Vector3d { return r * p; };
  const auto plus_left = [](const Eigen::Quaterniond& r, const Eigen::Vector3d& d) { return expSO3(d) * r; };
  const auto J = numericJacobian<3>(rotate, q, plus_left);
  static_assert(std::is_same_v<std::decay_t<decltype(J)>, Eigen::Matrix3d>, "fixed-size result");
  EXPECT_MATRIX_NEAR(J, -hat(q * p), 1e-8);
}

}  // namespace
}  // namespace vifusion
