#pragma once
// The camera's noise model (core/camera_noise_model.hpp) from the residuals of many frame pairs
// (pair_residuals.hpp). Each residual is the difference of two independent measurements, so the sensor's
// variance is half the residuals'.
//
// Robust variance. Occlusions, moving objects and pose errors give residuals far outside the noise. A set's
// variance is taken over the residuals within trim_sigmas robust σ (1.4826 × the median absolute deviation)
// of the median: at 4 σ this keeps 99.994 % of Gaussian noise (its variance comes out 0.1 % low) and drops
// the outliers.
// Depth. The model σ_ι² = A + B / z⁴ + L·‖∇ι‖² (disparity noise A = (σ_d / f·b)², quantisation B = q²/12, the
// inverse-depth image of q's uniform rounding, lateral noise L = σ_px²) is fitted to the squared residuals
// (variance_fit.hpp). The first fit keeps the residuals within trim_sigmas of their depth bin's robust σ;
// each refit trims at trim_sigmas of the previous fit's σ for that residual (kRefits times).
// Intensity. Per pair, a brightness change I_b = α·I_a + β (auto exposure) is fitted by least squares to the
// trimmed pairs and removed; then σ_I² + σ_px²·‖∇I‖² is fitted as for depth, with one bin.
// Bias. A bias left in inverse depth adds k·δb to each depth residual (pair_residuals.hpp); δb is their weighted
// least-squares fit over the inliers (bias_fit.hpp), w = 1 / var(r), the inlier window centred on the previous
// fit's prediction (kRefits times) so that residuals moved by k·δb are not trimmed more on one side. Its σ is
// clustered by pair: errors shared across a whole image, such as a depth staircase, make the pixels far from
// independent for this mean, beyond any correlation window.
// Correlation. Residuals divided by their fitted σ (√2 σ per pair) feed residual_correlation.hpp; those beyond
// trim_sigmas are left out.

#include <cstdint>
#include <vector>

#include "vifusion/calib/pair_residuals.hpp"
#include "vifusion/core/camera_noise_model.hpp"
#include "vifusion/core/image.hpp"

namespace vifusion::calib {

struct NoiseEstimatorOptions {
  double depth_bin_m = 0.25;            ///< width of a depth bin [m], > 0
  std::int64_t min_bin_samples = 1000;  ///< fewer residuals leave a bin out of the fit (σ within ±5 %), ≥ 10
  double trim_sigmas = 4.0;             ///< robust trimming bound [σ], > 2 (see above)
  int max_lag_px = 6;                   ///< correlation window half-width [px], in [1, 32]
  std::int64_t min_intensity_pair_samples = 1000;  ///< fewer leave a pair's intensity out, ≥ 10

  /// Throws vifusion::Error naming the field out of range.
  void validate() const;
};

struct DepthBinNoise {
  double z_m = 0.0;                      ///< mean depth of the bin's residuals [m]
  std::int64_t samples = 0;              ///< residuals kept by the bin's robust trimming
  double inverse_depth_sigma_per_m = 0;  ///< σ_ι measured in the bin [1/m] (every surface slant)
  double fitted_sigma_per_m = 0;         ///< the fitted model's RMS σ_ι over the same residuals [1/m]
};

struct NoiseEstimate {
  CameraNoiseModel model;
  std::vector<DepthBinNoise> depth_bins;  ///< the bins the fit used, nearest first
  /// Inverse-depth bias left after the calibration the frames were read with [1/m]: add it to that calibration's
  /// inverse_depth_bias_per_m. Its σ from the pairs' scatter (0 with fewer than two pairs).
  double remaining_inverse_depth_bias_per_m = 0.0;
  double remaining_inverse_depth_bias_sigma_per_m = 0.0;
  std::int64_t depth_samples = 0;      ///< depth residuals kept after trimming
  std::int64_t intensity_samples = 0;  ///< intensity residuals kept after trimming
  int pairs = 0;                       ///< frame pairs added
};

class NoiseEstimator {
 public:
  /// focal_baseline_px_m: the sensor's f·b (> 0, std::invalid_argument otherwise), which turns the measured
  /// inverse-depth noise into disparity noise.
  NoiseEstimator(double focal_baseline_px_m, const NoiseEstimatorOptions& options = {});

  /// Keeps the pair's depth residuals and its brightness-corrected intensity residuals (a copy).
  /// std::invalid_argument when its images differ in size.
  void addPair(const PairResidualImages& residuals);

  /// Fits the model. Throws vifusion::Error when no depth bin or too few intensity residuals were seen (the
  /// ground truth does not match the images, or the pairs do not overlap).
  NoiseEstimate estimate() const;

 private:
  struct StoredPair {
    Image<float> inverse_depth_residual_per_m;
    Image<float> depth_b_m;
    Image<float> inverse_depth_gradient_sq;
    Image<float> bias_sensitivity;
    Image<float> intensity_residual;  ///< after the pair's brightness fit; NaN where none
    Image<float> grey_gradient_sq;
  };

  double focal_baseline_px_m_;
  NoiseEstimatorOptions options_;
  std::vector<StoredPair> pairs_;
};

}  // namespace vifusion::calib
