// stepWithinUncertainty: the quantile is χ²(6)'s 0.01 quantile, and the test measures a step in the estimate's
// own uncertainty, not in metres.

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <random>

#include "vifusion/core/step_convergence.hpp"

namespace vifusion {
namespace {

// χ²(6)'s CDF in closed form: P(3, x/2) = 1 − e^{−y}(1 + y + y²/2), y = x/2.
double chi2SixDofCdf(double x) {
  const double y = 0.5 * x;
  return 1.0 - std::exp(-y) * (1.0 + y + 0.5 * y * y);
}

TEST(StepConvergence, QuantileIsTheOnePercentPointOfChiSquareWithSixDof) {
  EXPECT_NEAR(chi2SixDofCdf(kChi2SixDofQuantile001), 0.01, 1e-5);
}

TEST(StepConvergence, OnePercentOfDrawsFromTheEstimatesUncertaintyAreShorter) {
  // Steps drawn from N(0, H⁻¹) for an anisotropic H (a view that pins rotation far better than translation):
  // the share the test calls converged is the quantile's probability, whatever the units of H.
  Matrix6d information = Matrix6d::Zero();
  information.diagonal() << 4e6, 1e8, 2.5e7, 9e9, 3e10, 1e9;  // [1/m²] and [1/rad²]
  information(0, 4) = information(4, 0) = 1e8;                // translation-rotation coupling
  const Eigen::LLT<Matrix6d> llt(information);
  ASSERT_EQ(llt.info(), Eigen::Success);
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  constexpr int kDraws = 200000;
  int within = 0;
  for (int i = 0; i < kDraws; ++i) {
    Vector6d z;
    for (int k = 0; k < 6; ++k) z[k] = normal(rng);
    const Vector6d step = llt.matrixU().solve(z);  // Uᵀ U = H, so Cov(U⁻¹ z) = H⁻¹
    within += stepWithinUncertainty(step, information, kChi2SixDofQuantile001) ? 1 : 0;
  }
  // Binomial σ at p = 0.01 over 200 000 draws: 2.2e-4.
  EXPECT_NEAR(static_cast<double>(within) / kDraws, 0.01, 1e-3);
}

TEST(StepConvergence, TheSameStepInMetresIsConvergedOrNotByWhatTheViewDetermines) {
  Vector6d step = Vector6d::Zero();
  step[2] = 20e-6;  // 20 µm along the optical axis
  Matrix6d far_wall = Matrix6d::Identity() * 1e6;
  Matrix6d near_desk = Matrix6d::Identity() * 1e10;
  EXPECT_TRUE(stepWithinUncertainty(step, far_wall, kChi2SixDofQuantile001));    // 4e-4
  EXPECT_FALSE(stepWithinUncertainty(step, near_desk, kChi2SixDofQuantile001));  // 4
}

}  // namespace
}  // namespace vifusion
