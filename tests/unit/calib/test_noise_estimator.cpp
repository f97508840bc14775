#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "vifusion/calib/noise_estimator.hpp"
#include "vifusion/calib/pair_residuals.hpp"
#include "vifusion/core/error.hpp"

namespace vifusion::calib {
namespace {

constexpr double kFocalBaseline_px_m = 36.0;

/// Residual images drawn from a known model: σ_ι² = A + B/z⁴ + L·g², grey σ_I with a brightness change,
/// and a share of gross outliers (occlusions) in both.
PairResidualImages drawPair(std::mt19937& rng, const DepthNoiseModel& depth, double grey_sigma, double outlier_share,
                            double bias_per_m) {
  constexpr int kWidth = 160, kHeight = 120;
  PairResidualImages pair;
  pair.resize(kWidth, kHeight);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  const double a = depth.inverseDepthSigma() * depth.inverseDepthSigma();
  const double b = depth.quantisation_m * depth.quantisation_m / 12.0;
  const double l = depth.lateral_sigma_px * depth.lateral_sigma_px;
  for (std::size_t i = 0; i < pair.depth_b_m.pixelCount(); ++i) {
    const double z = 1.0 + 4.0 * uniform(rng);
    const double g2 = 1e-5 * uniform(rng);
    const double variance = a + b / (z * z * z * z) + l * g2;
    const bool outlier = uniform(rng) < outlier_share;
    pair.depth_b_m.data()[i] = static_cast<float>(z);
    pair.inverse_depth_gradient_sq.data()[i] = static_cast<float>(g2);
    const double k = 0.4 * (uniform(rng) - 0.5);  // depth changes by up to ±10 % between the frames
    pair.bias_sensitivity.data()[i] = static_cast<float>(k);
    pair.inverse_depth_residual_per_m.data()[i] = static_cast<float>(
        outlier ? 0.2 * (uniform(rng) - 0.5) : k * bias_per_m + std::sqrt(2.0 * variance) * normal(rng));
    const double grey_a = 20.0 + 200.0 * uniform(rng);
    pair.grey_a.data()[i] = static_cast<float>(grey_a);
    pair.grey_gradient_sq.data()[i] = 0.0F;
    const double grey_noise = outlier ? 100.0 * (uniform(rng) - 0.5) : std::sqrt(2.0) * grey_sigma * normal(rng);
    pair.grey_b_at_a.data()[i] = static_cast<float>(1.1 * grey_a + 3.0 + grey_noise);
  }
  return pair;
}

TEST(NoiseEstimator, RecoversAKnownModelPastOutliersAndABrightnessChange) {
  const DepthNoiseModel truth{.disparity_sigma_px = 0.05,
                              .focal_baseline_px_m = kFocalBaseline_px_m,
                              .quantisation_m = 0.01,
                              .lateral_sigma_px = 0.5,
                              .correlation_px = 0.0,
                              .pixels_per_sample = 1.0};
  std::mt19937 rng(11);
  NoiseEstimator estimator(kFocalBaseline_px_m);
  constexpr double kBias_per_m = 1.5e-3;
  for (int pair = 0; pair < 30; ++pair) estimator.addPair(drawPair(rng, truth, 2.7, 0.03, kBias_per_m));
  const NoiseEstimate estimate = estimator.estimate();
  EXPECT_NEAR(estimate.model.depth.disparity_sigma_px, 0.05, 0.02 * 0.05);
  EXPECT_NEAR(estimate.model.depth.quantisation_m, 0.01, 0.03 * 0.01);
  EXPECT_NEAR(estimate.model.depth.lateral_sigma_px, 0.5, 0.1 * 0.5);  // L·g² is ≤ 40 % of the variance
  // The outliers that fall inside the 4σ trimming window (0.9 % of residuals) add ≈ 2 % to σ.
  EXPECT_NEAR(estimate.model.intensity.sigma, 2.7, 0.04 * 2.7);
  EXPECT_NEAR(estimate.model.depth.pixels_per_sample, 1.0, 0.5);
  EXPECT_NEAR(estimate.model.intensity.pixels_per_sample, 1.0, 0.5);
  EXPECT_EQ(estimate.pairs, 30);
  // Independent residuals: the pairs' scatter gives the statistical σ, and the bias is within 3 of them.
  EXPECT_NEAR(estimate.remaining_inverse_depth_bias_per_m, kBias_per_m,
              3.0 * estimate.remaining_inverse_depth_bias_sigma_per_m);
  EXPECT_LT(estimate.remaining_inverse_depth_bias_sigma_per_m, 0.1 * kBias_per_m);
  EXPECT_FALSE(estimate.depth_bins.empty());
  for (const DepthBinNoise& bin : estimate.depth_bins) {
    EXPECT_NEAR(bin.inverse_depth_sigma_per_m, bin.fitted_sigma_per_m, 0.05 * bin.fitted_sigma_per_m) << bin.z_m;
  }
}

TEST(NoiseEstimator, RejectsAPairWhoseImagesDifferInSize) {
  std::mt19937 rng(1);
  PairResidualImages pair =
      drawPair(rng, DepthNoiseModel{.disparity_sigma_px = 0.05, .focal_baseline_px_m = 36.0}, 2.7, 0.0, 0.0);
  pair.bias_sensitivity.resize(8, 8);
  NoiseEstimator estimator(kFocalBaseline_px_m);
  EXPECT_THROW(estimator.addPair(pair), std::invalid_argument);
}

TEST(NoiseEstimator, NoPairsIsAnErrorThatSaysWhy) {
  NoiseEstimator estimator(kFocalBaseline_px_m);
  try {
    (void)estimator.estimate();
    FAIL() << "expected an error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("ground-truth poses"), std::string::npos) << error.what();
  }
}

TEST(NoiseEstimator, RejectsOptionsOutOfRange) {
  EXPECT_THROW(NoiseEstimator(0.0), std::invalid_argument);
  EXPECT_THROW(NoiseEstimator(36.0, NoiseEstimatorOptions{.depth_bin_m = 0.0}), Error);
  EXPECT_THROW(NoiseEstimator(36.0, NoiseEstimatorOptions{.trim_sigmas = 1.5}), Error);
}

}  // namespace
}  // namespace vifusion::calib
