#pragma once
// GoogleTest helpers for Eigen results. On failure they print both matrices in full precision, the
// difference and where the largest element-wise difference sits, which is what one needs to debug a
// Jacobian:
//   EXPECT_MATRIX_NEAR(J_analytic, J_numeric, 1e-6);
//   EXPECT_TRUE(vifusion::test::matricesNear(a, b, 1e-9));
//   EXPECT_ROTATION_NEAR(q_estimated, q_expected, 1e-9);   // angle between rotations [rad], sign-free

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <sstream>

namespace vifusion::test {

namespace detail {

inline const Eigen::IOFormat& fullPrecision() {
  static const Eigen::IOFormat format(Eigen::FullPrecision, 0, ", ", "\n", "  [", "]");
  return format;
}

}  // namespace detail

/// Passes when a and b have the same size and every |a_ij − b_ij| ≤ tol (NaN never passes).
template <class A, class B>
::testing::AssertionResult matricesNearFormat(const char* a_expr, const char* b_expr, const char* /*tol_expr*/,
                                              const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b,
                                              double tol) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) {
    return ::testing::AssertionFailure() << a_expr << " is " << a.rows() << "x" << a.cols() << " but " << b_expr
                                         << " is " << b.rows() << "x" << b.cols();
  }
  const Eigen::MatrixXd a_d = a.template cast<double>();
  const Eigen::MatrixXd b_d = b.template cast<double>();
  const Eigen::MatrixXd diff = a_d - b_d;
  // Largest |difference|, with NaN and ±inf counted as infinite so they can never pass.
  double max_diff = 0.0;
  Eigen::Index max_row = 0;
  Eigen::Index max_col = 0;
  for (Eigen::Index c = 0; c < diff.cols(); ++c) {
    for (Eigen::Index r = 0; r < diff.rows(); ++r) {
      const double d = std::isfinite(diff(r, c)) ? std::abs(diff(r, c)) : std::numeric_limits<double>::infinity();
      if (d > max_diff) {
        max_diff = d;
        max_row = r;
        max_col = c;
      }
    }
  }
  if (max_diff <= tol) return ::testing::AssertionSuccess();

  std::ostringstream os;
  os.precision(17);
  os << a_expr << " and " << b_expr << " differ by " << max_diff << " at (" << max_row << ", " << max_col
     << "), tolerance " << tol << "\n"
     << a_expr << " =\n"
     << a_d.format(detail::fullPrecision()) << "\n"
     << b_expr << " =\n"
     << b_d.format(detail::fullPrecision()) << "\n"
     << "difference =\n"
     << diff.format(detail::fullPrecision());
  return ::testing::AssertionFailure() << os.str();
}

/// Same check for use inside EXPECT_TRUE / ASSERT_TRUE.
template <class A, class B>
::testing::AssertionResult matricesNear(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b, double tol) {
  return matricesNearFormat("a", "b", "tol", a, b, tol);
}

/// Passes when the rotations of q_a and q_b (either sign, any norm) differ by at most tol_rad.
inline ::testing::AssertionResult rotationsNearFormat(const char* a_expr, const char* b_expr, const char* /*tol_expr*/,
                                                      const Eigen::Quaterniond& q_a, const Eigen::Quaterniond& q_b,
                                                      double tol_rad) {
  const Eigen::Quaterniond d = q_a.normalized() * q_b.normalized().conjugate();
  const double angle_rad = 2.0 * std::atan2(d.vec().norm(), std::abs(d.w()));
  if (angle_rad <= tol_rad) return ::testing::AssertionSuccess();
  std::ostringstream os;
  os.precision(17);
  os << a_expr << " and " << b_expr << " differ by " << angle_rad << " rad, tolerance " << tol_rad << "\n"
     << a_expr << " (w, x, y, z) = " << q_a.w() << ", " << q_a.x() << ", " << q_a.y() << ", " << q_a.z() << "\n"
     << b_expr << " (w, x, y, z) = " << q_b.w() << ", " << q_b.x() << ", " << q_b.y() << ", " << q_b.z();
  return ::testing::AssertionFailure() << os.str();
}

}  // namespace vifusion::test

#define EXPECT_MATRIX_NEAR(a, b, tol) EXPECT_PRED_FORMAT3(::vifusion::test::matricesNearFormat, a, b, tol)
#define ASSERT_MATRIX_NEAR(a, b, tol) ASSERT_PRED_FORMAT3(::vifusion::test::matricesNearFormat, a, b, tol)
#define EXPECT_ROTATION_NEAR(q_a, q_b, tol_rad) \
  EXPECT_PRED_FORMAT3(::vifusion::test::rotationsNearFormat, q_a, q_b, tol_rad)
#define ASSERT_ROTATION_NEAR(q_a, q_b, tol_rad) \
  ASSERT_PRED_FORMAT3(::vifusion::test::rotationsNearFormat, q_a, q_b, tol_rad)
