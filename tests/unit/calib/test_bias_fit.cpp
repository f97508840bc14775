#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "vifusion/calib/bias_fit.hpp"

namespace vifusion::calib {
namespace {

TEST(BiasFit, RecoversTheBiasFromExactResiduals) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> k(-0.2, 0.2);
  BiasFit fit;
  for (int pair = 0; pair < 3; ++pair) {
    fit.beginPair();
    for (int i = 0; i < 50; ++i) {
      const double sensitivity = k(rng);
      fit.add(sensitivity, sensitivity * 1.4e-3, 1.0);
    }
  }
  const BiasEstimate solved = fit.solve();
  EXPECT_NEAR(solved.bias_per_m, 1.4e-3, 1e-15);
  EXPECT_LT(solved.sigma_per_m, 1e-15);  // nothing left over
}

TEST(BiasFit, NothingThatConstrainsTheBiasGivesZero) {
  BiasFit fit;
  EXPECT_EQ(fit.solve().bias_per_m, 0.0);
  fit.beginPair();
  fit.add(0.0, 1e-3, 1.0);  // a pair that moved across the view: k = 0
  EXPECT_EQ(fit.solve().bias_per_m, 0.0);
  EXPECT_EQ(fit.solve().sigma_per_m, 0.0);
}

TEST(BiasFit, ClusteredSigmaHoldsAnErrorSharedByAWholePair) {
  // Each pair's residuals share a random bias β_p (a depth staircase common to one image pair) on top of
  // independent pixel noise, and pairs differ in how much they see (their k range). Over repeated experiments the
  // estimates scatter by the reported σ, while the σ that treats every pixel as independent is several times
  // smaller.
  constexpr int kExperiments = 300, kPairs = 20, kPixels = 1000;
  constexpr double kPixelSigma = 2e-3, kSharedSigma = 2e-3, kBias = 1.4e-3;
  std::mt19937 rng(5);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  double sum = 0.0, sum_sq = 0.0, reported_variance = 0.0, independent_variance = 0.0;
  for (int experiment = 0; experiment < kExperiments; ++experiment) {
    BiasFit fit;
    double information = 0.0;
    for (int pair = 0; pair < kPairs; ++pair) {
      fit.beginPair();
      const double shared = kSharedSigma * normal(rng);
      const double k_range = 0.05 + 0.25 * (pair % 4) / 3.0;  // sideways to along the view
      for (int i = 0; i < kPixels; ++i) {
        const double k = k_range * uniform(rng);
        const double weight = 1.0 / (kPixelSigma * kPixelSigma);
        fit.add(k, k * (kBias + shared) + kPixelSigma * normal(rng), weight);
        information += weight * k * k;
      }
    }
    const BiasEstimate solved = fit.solve();
    sum += solved.bias_per_m;
    sum_sq += solved.bias_per_m * solved.bias_per_m;
    reported_variance += solved.sigma_per_m * solved.sigma_per_m / kExperiments;
    independent_variance += 1.0 / information / kExperiments;
  }
  const double mean = sum / kExperiments;
  const double scatter = std::sqrt(sum_sq / kExperiments - mean * mean);
  std::printf("bias scatter %.3g, reported σ %.3g, σ of independent pixels %.3g 1/m\n", scatter,
              std::sqrt(reported_variance), std::sqrt(independent_variance));
  EXPECT_NEAR(mean, kBias, 3.0 * scatter / std::sqrt(double{kExperiments}));
  EXPECT_NEAR(std::sqrt(reported_variance), scatter, 0.15 * scatter);
  EXPECT_GT(scatter, 2.0 * std::sqrt(independent_variance));
}

}  // namespace
}  // namespace vifusion::calib
