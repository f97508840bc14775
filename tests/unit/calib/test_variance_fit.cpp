#include <gtest/gtest.h>

#include <random>

#include "vifusion/calib/variance_fit.hpp"

namespace vifusion::calib {
namespace {

// Residuals are differences of two measurements, so they carry twice the modelled variance.
double drawResidual(std::mt19937& rng, double variance) {
  return std::normal_distribution<double>(0.0, std::sqrt(2.0 * variance))(rng);
}

TEST(VarianceFit, RecoversEveryTermOfAKnownModel) {
  const Eigen::Vector3d truth(2e-6, 8e-7, 0.25);  // A, B, L as in the depth model
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> depth(1.0, 5.0), gradient_sq(0.0, 1e-5);
  VarianceFit<3> fit;
  for (int i = 0; i < 400000; ++i) {
    const double z = depth(rng);
    const VarianceFit<3>::Features f(1.0, 1.0 / (z * z * z * z), gradient_sq(rng));
    const double variance = truth.dot(f);
    fit.add(drawResidual(rng, variance), f, 1.0 / (variance * variance));
  }
  const Eigen::Vector3d c = fit.solve();
  EXPECT_NEAR(c(0), truth(0), 0.03 * truth(0));
  EXPECT_NEAR(c(1), truth(1), 0.1 * truth(1));  // B/z⁴ < A at every depth drawn: the least-determined term
  EXPECT_NEAR(c(2), truth(2), 0.03 * truth(2));
  EXPECT_EQ(fit.samples(), 400000);
}

TEST(VarianceFit, DropsATermTheDataDoNotSupportAndRefitsTheRest) {
  // Pure constant noise: the fit of the gradient term scatters about 0; clamped, A keeps its value.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> gradient_sq(0.0, 4.0);
  VarianceFit<2> fit;
  for (int i = 0; i < 100000; ++i)
    fit.add(drawResidual(rng, 4.0), VarianceFit<2>::Features(1.0, gradient_sq(rng)), 1.0);
  const Eigen::Vector2d c = fit.solve();
  EXPECT_GE(c(1), 0.0);
  EXPECT_NEAR(c(0), 4.0, 0.1);
}

TEST(VarianceFit, NothingAddedGivesZero) { EXPECT_EQ(VarianceFit<2>().solve(), Eigen::Vector2d::Zero()); }

}  // namespace
}  // namespace vifusion::calib
