#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <cstdio>
#include <random>

#include "vifusion/calib/depth_offset_fit.hpp"

namespace vifusion::calib {
namespace {

/// A row as pair residuals give it: k up to ±0.2, ∂r/∂s up to ±1e-3 1/m per px.
DepthOffsets::Vector drawRow(std::mt19937& rng) {
  std::uniform_real_distribution<double> k(-0.2, 0.2), slope(-1e-3, 1e-3);
  return {k(rng), slope(rng), slope(rng)};
}

TEST(DepthOffsetFit, RecoversOffsetsFromExactResiduals) {
  const DepthOffsets::Vector truth(1.4e-3, 0.1, -0.2);
  std::mt19937 rng(3);
  DepthOffsetFit fit;
  for (int pair = 0; pair < 3; ++pair) {
    fit.beginPair();
    for (int i = 0; i < 50; ++i) {
      const DepthOffsets::Vector row = drawRow(rng);
      fit.add(row, row.dot(truth), 1.0);
    }
  }
  const DepthOffsets solved = fit.solve();
  EXPECT_NEAR(solved.value(0), truth(0), 1e-12);
  EXPECT_NEAR(solved.value(1), truth(1), 1e-9);
  EXPECT_NEAR(solved.value(2), truth(2), 1e-9);
  EXPECT_LT(solved.covariance.norm(), 1e-20);  // nothing left over
}

TEST(DepthOffsetFit, ADirectionNoPairSeesComesOutZero) {
  // Fronto-parallel walls: no slope, so the shift is not observable; the bias still is.
  std::mt19937 rng(4);
  std::normal_distribution<double> noise(0.0, 1e-4);
  DepthOffsetFit fit;
  for (int pair = 0; pair < 4; ++pair) {
    fit.beginPair();
    for (int i = 0; i < 100; ++i) {
      const DepthOffsets::Vector row(drawRow(rng).x(), 0.0, 0.0);
      fit.add(row, row.x() * 1e-3 + noise(rng), 1.0);
    }
  }
  const DepthOffsets solved = fit.solve();
  EXPECT_NEAR(solved.value(0), 1e-3, 1e-4);
  EXPECT_EQ(solved.value(1), 0.0);
  EXPECT_EQ(solved.value(2), 0.0);
  EXPECT_GT(solved.covariance(0, 0), 0.0);
  const Eigen::Matrix2d shift_covariance = solved.covariance.bottomRightCorner<2, 2>();
  EXPECT_LT(shift_covariance.norm(), 1e-30);
}

TEST(DepthOffsetFit, ClusteredCovarianceHoldsAnErrorSharedByAWholePair) {
  // Each pair's residuals share a random bias β_p (a depth staircase common to one image pair) on top of
  // independent pixel noise. Over repeated experiments the estimates scatter by the reported σ, while the σ that
  // treats every pixel as independent is several times smaller.
  constexpr int kExperiments = 300, kPairs = 20, kPixels = 1000;
  constexpr double kPixelSigma = 2e-3, kSharedSigma = 2e-3;
  const DepthOffsets::Vector truth(1.4e-3, 0.05, 0.0);
  std::mt19937 rng(5);
  std::normal_distribution<double> normal(0.0, 1.0);
  double sum = 0.0, sum_sq = 0.0, reported_variance = 0.0, independent_variance = 0.0;
  for (int experiment = 0; experiment < kExperiments; ++experiment) {
    DepthOffsetFit fit;
    Eigen::Matrix3d normal_matrix = Eigen::Matrix3d::Zero();
    for (int pair = 0; pair < kPairs; ++pair) {
      fit.beginPair();
      const double shared = kSharedSigma * normal(rng);
      for (int i = 0; i < kPixels; ++i) {
        const DepthOffsets::Vector row = drawRow(rng);
        const double weight = 1.0 / (kPixelSigma * kPixelSigma);
        fit.add(row, row.dot(truth) + row.x() * shared + kPixelSigma * normal(rng), weight);
        normal_matrix += weight * row * row.transpose();
      }
    }
    const DepthOffsets solved = fit.solve();
    sum += solved.value(0);
    sum_sq += solved.value(0) * solved.value(0);
    reported_variance += solved.covariance(0, 0) / kExperiments;
    independent_variance += normal_matrix.inverse()(0, 0) / kExperiments;
  }
  const double mean = sum / kExperiments;
  const double scatter = std::sqrt(sum_sq / kExperiments - mean * mean);
  std::printf("bias scatter %.3g, reported σ %.3g, σ of independent pixels %.3g 1/m\n", scatter,
              std::sqrt(reported_variance), std::sqrt(independent_variance));
  EXPECT_NEAR(mean, truth(0), 3.0 * scatter / std::sqrt(double{kExperiments}));
  EXPECT_NEAR(std::sqrt(reported_variance), scatter, 0.15 * scatter);
  EXPECT_GT(scatter, 2.0 * std::sqrt(independent_variance));
}

}  // namespace
}  // namespace vifusion::calib
