#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "vifusion/synccheck/robust_line_fit.hpp"

namespace vifusion::synccheck {
namespace {

TEST(SynccheckLineFit, ExactLineIsRecovered) {
  std::vector<double> x, y;
  for (int i = 0; i < 100; ++i) {
    x.push_back(0.1 * i);
    y.push_back(3.0 - 2.5 * x.back());
  }
  const LineFit fit = fitRobustLine(x, y);
  ASSERT_TRUE(fit.valid());
  EXPECT_NEAR(fit.intercept, 3.0, 1e-12);
  EXPECT_NEAR(fit.slope, -2.5, 1e-12);
  EXPECT_EQ(fit.scale, 0.0);
  EXPECT_EQ(fit.inliers, 100u);
}

// 20 % of the points 50 σ above the line: Tukey's weights drop them entirely, where least squares would
// move the intercept by 0.2 × 50 σ = 10 σ.
TEST(SynccheckLineFit, GrossOutliersChangeNothing) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<double> x, y;
  double ols_sum = 0.0;
  for (int i = 0; i < 2000; ++i) {
    x.push_back(0.03 * i);
    const bool outlier = i % 5 == 0;
    y.push_back(100.0 + 4.0 * x.back() + noise(rng) + (outlier ? 50.0 : 0.0));
    ols_sum += y.back() - 4.0 * x.back();
  }
  const LineFit fit = fitRobustLine(x, y);
  ASSERT_TRUE(fit.valid());
  EXPECT_NEAR(fit.intercept, 100.0, 0.15);  // ~3 standard errors of 1/√1600 · 2
  EXPECT_NEAR(fit.slope, 4.0, 0.01);
  // The scale is the MAD of all residuals, outliers included: the 0.625 quantile of |N(0, 1)| (0.887)
  // × 1.4826 = 1.315. Only the weights' cut-off (4.685 × 1.315 = 6.2 σ) depends on it.
  EXPECT_NEAR(fit.scale, 1.315, 0.1);
  EXPECT_NEAR(static_cast<double>(fit.inliers), 1600.0, 10.0);
  EXPECT_GT(ols_sum / 2000.0 - 100.0, 9.0);  // what least squares' intercept would have been off by
}

// More points than the Theil–Sen start takes: the IRLS still uses all of them (accuracy of √n).
TEST(SynccheckLineFit, LongInputsUseEveryPoint) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> noise(0.0, 10.0);
  std::vector<double> x, y;
  for (int i = 0; i < 50'000; ++i) {
    x.push_back(1e-3 * i);
    y.push_back(-7.0 + 0.5 * x.back() + noise(rng));
  }
  const LineFit fit = fitRobustLine(x, y);
  EXPECT_NEAR(fit.intercept, -7.0, 0.3);  // σ·2/√n = 0.09
  EXPECT_NEAR(fit.slope, 0.5, 0.01);      // σ/√(n·T²/12) = 0.003
  EXPECT_GT(fit.iterations, 0);
}

TEST(SynccheckLineFit, DegenerateInputGivesNaNNotACrash) {
  const std::vector<double> none;
  EXPECT_FALSE(fitRobustLine(none, none).valid());
  const std::vector<double> one_x{2.0}, one_y{5.0};
  const LineFit single = fitRobustLine(one_x, one_y);
  EXPECT_FALSE(single.valid());
  EXPECT_EQ(single.intercept, 5.0);
  EXPECT_TRUE(std::isnan(single.slope));
  const std::vector<double> same_x{1.0, 1.0, 1.0}, ys{4.0, 6.0, 5.0};
  const LineFit vertical = fitRobustLine(same_x, ys);
  EXPECT_TRUE(std::isnan(vertical.slope));
  EXPECT_EQ(vertical.intercept, 5.0);
  const std::vector<double> short_y{1.0};
  EXPECT_FALSE(fitRobustLine(same_x, short_y).valid());  // mismatched lengths
}

}  // namespace
}  // namespace vifusion::synccheck
