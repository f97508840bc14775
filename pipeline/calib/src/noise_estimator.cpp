#include "vifusion/calib/noise_estimator.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "vifusion/calib/bias_fit.hpp"
#include "vifusion/calib/residual_correlation.hpp"
#include "vifusion/calib/variance_fit.hpp"
#include "vifusion/core/error.hpp"

namespace vifusion::calib {
namespace {

constexpr float kNone = std::numeric_limits<float>::quiet_NaN();
/// σ = 1.4826 × median absolute deviation for Gaussian data.
constexpr double kMadToSigma = 1.4826;
constexpr std::int64_t kSmallestSampleCount = 10;
/// Refits after the first: the trimming settles after two (the kept set changes by < 0.1 % on the third).
constexpr int kRefits = 3;
/// Floor of a fitted variance, so that weights 1/σ⁴ stay finite where every term came out zero.
constexpr double kSmallestVariance = 1e-300;
/// Depth model terms: A, B / z⁴, L·‖∇ι‖².
using DepthFit = VarianceFit<3>;
/// Intensity model terms: σ_I², σ_px²·‖∇I‖².
using IntensityFit = VarianceFit<2>;

double median(std::vector<double>& values) {
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

/// The interval [centre − half_width, centre + half_width] holding a set's inliers.
struct TrimWindow {
  double centre = 0.0;
  double half_width = 0.0;
  bool contains(double value) const { return std::abs(value - centre) <= half_width; }
};

TrimWindow trimWindow(std::vector<double> values, double trim_sigmas) {
  const double centre = median(values);
  for (double& value : values) value = std::abs(value - centre);
  return {centre, trim_sigmas * kMadToSigma * median(values)};
}

/// Variance about the mean of the values inside `window`, and their count.
std::pair<double, std::int64_t> trimmedVariance(const std::vector<double>& values, const TrimWindow& window) {
  double sum = 0.0;
  double sum_sq = 0.0;
  std::int64_t count = 0;
  for (const double value : values) {
    if (!window.contains(value)) continue;
    sum += value;
    sum_sq += value * value;
    ++count;
  }
  if (count < 2) return {0.0, count};
  const double mean = sum / static_cast<double>(count);
  return {(sum_sq - static_cast<double>(count) * mean * mean) / static_cast<double>(count - 1), count};
}

/// The sensor's variance the fitted coefficients give for a residual with these features (floored).
template <int N>
double modelVariance(const typename VarianceFit<N>::Coefficients& coefficients,
                     const typename VarianceFit<N>::Features& features) {
  return std::max(coefficients.dot(features), kSmallestVariance);
}

/// A residual of a pair (variance 2·σ² for the sensor's σ²) within trim_sigmas of zero.
bool isInlier(double residual, double variance, double trim_sigmas) {
  return std::abs(residual) <= trim_sigmas * std::sqrt(2.0 * variance);
}

/// kRefits weighted refits from `start`, each over the residuals within trim_sigmas of the previous fit;
/// for_each(visit) calls visit(pair, i, r, features) for every residual. `samples` gets the last fit's count.
template <int N, class ForEach>
typename VarianceFit<N>::Coefficients refitTrimmed(typename VarianceFit<N>::Coefficients coefficients,
                                                   const ForEach& for_each, double trim_sigmas, std::int64_t& samples) {
  for (int refit = 0; refit < kRefits; ++refit) {
    VarianceFit<N> fit;
    for_each([&](const auto&, std::size_t, double r, const typename VarianceFit<N>::Features& f) {
      const double variance = modelVariance<N>(coefficients, f);
      if (isInlier(r, variance, trim_sigmas)) fit.add(r, f, 1.0 / (variance * variance));
    });
    coefficients = fit.solve();
    samples = fit.samples();
  }
  return coefficients;
}

/// Adds finite values of `image` to `out`.
void appendFinite(const Image<float>& image, std::vector<double>& out) {
  for (std::size_t i = 0; i < image.pixelCount(); ++i) {
    if (std::isfinite(image.data()[i])) out.push_back(image.data()[i]);
  }
}

}  // namespace

void NoiseEstimatorOptions::validate() const {
  const auto fail = [](const std::string& what) { throw Error("noise-estimator option " + what); };
  if (!(depth_bin_m > 0.0)) fail("'depth_bin_m' must be > 0");
  if (min_bin_samples < kSmallestSampleCount) fail("'min_bin_samples' must be ≥ 10");
  if (!(trim_sigmas > 2.0)) fail("'trim_sigmas' must be > 2");
  if (max_lag_px < 1 || max_lag_px > 32) fail("'max_lag_px' must be in [1, 32]");
  if (min_intensity_pair_samples < kSmallestSampleCount) fail("'min_intensity_pair_samples' must be ≥ 10");
}

NoiseEstimator::NoiseEstimator(double focal_baseline_px_m, const NoiseEstimatorOptions& options)
    : focal_baseline_px_m_(focal_baseline_px_m), options_(options) {
  if (!(focal_baseline_px_m > 0.0)) throw std::invalid_argument("noise estimator: f·b must be > 0 px·m");
  options_.validate();
}

void NoiseEstimator::addPair(const PairResidualImages& residuals) {
  const int width = residuals.inverse_depth_residual_per_m.width();
  const int height = residuals.inverse_depth_residual_per_m.height();
  for (const Image<float>* image :
       {&residuals.depth_b_m, &residuals.inverse_depth_gradient_sq, &residuals.bias_sensitivity, &residuals.grey_b_at_a,
        &residuals.grey_a, &residuals.grey_gradient_sq}) {
    if (image->width() != width || image->height() != height) {
      throw std::invalid_argument("noise estimator: a pair's residual images differ in size");
    }
  }
  StoredPair& pair = pairs_.emplace_back();
  pair.inverse_depth_residual_per_m = residuals.inverse_depth_residual_per_m;
  pair.depth_b_m = residuals.depth_b_m;
  pair.inverse_depth_gradient_sq = residuals.inverse_depth_gradient_sq;
  pair.bias_sensitivity = residuals.bias_sensitivity;
  pair.grey_gradient_sq = residuals.grey_gradient_sq;
  const Image<float>& grey_a = residuals.grey_a;
  const Image<float>& grey_b = residuals.grey_b_at_a;
  pair.intensity_residual.resize(grey_a.width(), grey_a.height(), kNone);

  std::vector<double> differences;
  for (std::size_t i = 0; i < grey_b.pixelCount(); ++i) {
    if (std::isfinite(grey_b.data()[i])) differences.push_back(grey_b.data()[i] - grey_a.data()[i]);
  }
  if (static_cast<std::int64_t>(differences.size()) < options_.min_intensity_pair_samples) return;
  const TrimWindow window = trimWindow(differences, options_.trim_sigmas);
  Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
  Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < grey_b.pixelCount(); ++i) {
    const double b = grey_b.data()[i];
    if (!std::isfinite(b) || !window.contains(b - grey_a.data()[i])) continue;
    const Eigen::Vector2d row(grey_a.data()[i], 1.0);
    normal += row * row.transpose();
    rhs += row * b;
  }
  const Eigen::Vector2d gain_offset = normal.ldlt().solve(rhs);
  for (std::size_t i = 0; i < grey_b.pixelCount(); ++i) {
    const double b = grey_b.data()[i];
    if (!std::isfinite(b)) continue;
    pair.intensity_residual.data()[i] = static_cast<float>(b - gain_offset.x() * grey_a.data()[i] - gain_offset.y());
  }
}

NoiseEstimate NoiseEstimator::estimate() const {
  NoiseEstimate estimate;
  estimate.pairs = static_cast<int>(pairs_.size());
  estimate.model.depth.focal_baseline_px_m = focal_baseline_px_m_;

  // Call visit(i, r, features) for every depth (intensity) residual of one pair.
  const auto for_each_depth_in = [](const StoredPair& pair, const auto& visit) {
    for (std::size_t i = 0; i < pair.depth_b_m.pixelCount(); ++i) {
      const double r = pair.inverse_depth_residual_per_m.data()[i];
      const double z = pair.depth_b_m.data()[i];
      if (!std::isfinite(r) || !std::isfinite(z)) continue;
      visit(i, r, DepthFit::Features(1.0, 1.0 / (z * z * z * z), pair.inverse_depth_gradient_sq.data()[i]));
    }
  };
  const auto for_each_intensity_in = [](const StoredPair& pair, const auto& visit) {
    for (std::size_t i = 0; i < pair.intensity_residual.pixelCount(); ++i) {
      const double r = pair.intensity_residual.data()[i];
      if (!std::isfinite(r)) continue;
      visit(i, r, IntensityFit::Features(1.0, pair.grey_gradient_sq.data()[i]));
    }
  };
  // Call visit(pair, i, r, features) for every residual of every pair.
  const auto for_each_depth = [&](const auto& visit) {
    for (const StoredPair& pair : pairs_) {
      for_each_depth_in(pair, [&](std::size_t i, double r, const DepthFit::Features& f) { visit(pair, i, r, f); });
    }
  };
  const auto for_each_intensity = [&](const auto& visit) {
    for (const StoredPair& pair : pairs_) {
      for_each_intensity_in(pair,
                            [&](std::size_t i, double r, const IntensityFit::Features& f) { visit(pair, i, r, f); });
    }
  };

  // Depth bins: the first trimming, and the per-depth table.
  const auto bin_of = [&](const StoredPair& pair, std::size_t i) {
    return static_cast<std::size_t>(pair.depth_b_m.data()[i] / options_.depth_bin_m);
  };
  std::vector<std::vector<double>> bin_residuals;
  for_each_depth([&](const StoredPair& pair, std::size_t i, double r, const DepthFit::Features&) {
    const std::size_t bin = bin_of(pair, i);
    if (bin >= bin_residuals.size()) bin_residuals.resize(bin + 1);
    bin_residuals[bin].push_back(r);
  });
  std::vector<TrimWindow> bin_window(bin_residuals.size());
  std::vector<double> bin_variance(bin_residuals.size(), 0.0);
  std::vector<bool> bin_used(bin_residuals.size(), false);
  for (std::size_t bin = 0; bin < bin_residuals.size(); ++bin) {
    if (static_cast<std::int64_t>(bin_residuals[bin].size()) < options_.min_bin_samples) continue;
    bin_window[bin] = trimWindow(bin_residuals[bin], options_.trim_sigmas);
    const auto [variance, count] = trimmedVariance(bin_residuals[bin], bin_window[bin]);
    if (count < options_.min_bin_samples || !(variance > 0.0)) continue;
    bin_variance[bin] = variance;
    bin_used[bin] = true;
  }
  bin_residuals.clear();
  if (std::none_of(bin_used.begin(), bin_used.end(), [](bool used) { return used; })) {
    throw Error("noise calibration: no depth bin collected " + std::to_string(options_.min_bin_samples) +
                " residuals from " + std::to_string(pairs_.size()) +
                " frame pairs (do the ground-truth poses belong to these images, and do the pairs overlap?)");
  }

  DepthFit first_depth;
  for_each_depth([&](const StoredPair& pair, std::size_t i, double r, const DepthFit::Features& f) {
    const std::size_t bin = bin_of(pair, i);
    if (!bin_used[bin] || !bin_window[bin].contains(r)) return;
    first_depth.add(r, f, 1.0 / (bin_variance[bin] * bin_variance[bin]));
  });
  DepthFit::Coefficients depth = first_depth.solve();
  const auto depth_variance = [&](const DepthFit::Features& f) { return modelVariance<3>(depth, f); };
  const auto kept = [&](double r, double variance) { return isInlier(r, variance, options_.trim_sigmas); };
  depth = refitTrimmed<3>(depth, for_each_depth, options_.trim_sigmas, estimate.depth_samples);
  DepthNoiseModel& depth_model = estimate.model.depth;
  depth_model.disparity_sigma_px = std::sqrt(depth(0)) * focal_baseline_px_m_;
  depth_model.quantisation_m = std::sqrt(12.0 * depth(1));
  depth_model.lateral_sigma_px = std::sqrt(depth(2));

  // The per-depth table: each bin's measured σ and the model's RMS σ over the same residuals.
  std::vector<double> bin_z(bin_used.size(), 0.0), bin_model(bin_used.size(), 0.0);
  std::vector<std::int64_t> bin_count(bin_used.size(), 0);
  for_each_depth([&](const StoredPair& pair, std::size_t i, double r, const DepthFit::Features& f) {
    const std::size_t bin = bin_of(pair, i);
    if (!bin_used[bin] || !bin_window[bin].contains(r)) return;
    bin_z[bin] += pair.depth_b_m.data()[i];
    bin_model[bin] += depth_variance(f);
    ++bin_count[bin];
  });
  for (std::size_t bin = 0; bin < bin_used.size(); ++bin) {
    if (!bin_used[bin]) continue;
    const double n = static_cast<double>(bin_count[bin]);
    estimate.depth_bins.push_back(
        {bin_z[bin] / n, bin_count[bin], std::sqrt(0.5 * bin_variance[bin]), std::sqrt(bin_model[bin] / n)});
  }

  // Intensity: one robust window for the first fit, then refits as for depth.
  std::vector<double> intensity;
  for (const StoredPair& pair : pairs_) appendFinite(pair.intensity_residual, intensity);
  if (static_cast<std::int64_t>(intensity.size()) < options_.min_intensity_pair_samples) {
    throw Error("noise calibration: only " + std::to_string(intensity.size()) + " intensity residuals from " +
                std::to_string(pairs_.size()) + " frame pairs");
  }
  const TrimWindow intensity_window = trimWindow(intensity, options_.trim_sigmas);
  intensity.clear();
  IntensityFit first_intensity;
  for_each_intensity([&](const StoredPair&, std::size_t, double r, const IntensityFit::Features& f) {
    if (intensity_window.contains(r)) first_intensity.add(r, f, 1.0);
  });
  IntensityFit::Coefficients grey = first_intensity.solve();
  const auto grey_variance = [&](const IntensityFit::Features& f) { return modelVariance<2>(grey, f); };
  grey = refitTrimmed<2>(grey, for_each_intensity, options_.trim_sigmas, estimate.intensity_samples);
  estimate.model.intensity.sigma = std::sqrt(grey(0));
  estimate.model.intensity.lateral_sigma_px = std::sqrt(grey(1));

  // Correlation of the residuals normalised by their fitted σ.
  ResidualCorrelation depth_correlation(options_.max_lag_px);
  ResidualCorrelation intensity_correlation(options_.max_lag_px);
  Image<float> depth_normalised, grey_normalised;
  for (const StoredPair& pair : pairs_) {
    const int width = pair.depth_b_m.width();
    const int height = pair.depth_b_m.height();
    depth_normalised.resize(width, height, kNone);
    grey_normalised.resize(width, height, kNone);
    const auto normalise = [&](double r, double variance) {
      return kept(r, variance) ? static_cast<float>(r / std::sqrt(2.0 * variance)) : kNone;
    };
    for_each_depth_in(pair, [&](std::size_t i, double r, const DepthFit::Features& f) {
      depth_normalised.data()[i] = normalise(r, depth_variance(f));
    });
    for_each_intensity_in(pair, [&](std::size_t i, double r, const IntensityFit::Features& f) {
      grey_normalised.data()[i] = normalise(r, grey_variance(f));
    });
    depth_correlation.add(depth_normalised.view());
    intensity_correlation.add(grey_normalised.view());
  }
  depth_model.correlation_px = depth_correlation.correlationLength_px();
  depth_model.pixels_per_sample = depth_correlation.pixelsPerSample();
  estimate.model.intensity.correlation_px = intensity_correlation.correlationLength_px();
  estimate.model.intensity.pixels_per_sample = intensity_correlation.pixelsPerSample();

  // The bias left in inverse depth, by weighted least squares over the inliers of the depth fit, the inlier window
  // centred on the previous solution; its σ clustered by pair.
  BiasFit bias;
  for (int refit = 0; refit < kRefits; ++refit) {
    const double previous = bias.solve().bias_per_m;
    bias = BiasFit();
    for (const StoredPair& pair : pairs_) {
      bias.beginPair();
      for_each_depth_in(pair, [&](std::size_t i, double r, const DepthFit::Features& f) {
        const double k = pair.bias_sensitivity.data()[i];
        const double variance = depth_variance(f);
        if (!std::isfinite(k) || !kept(r - k * previous, variance)) return;
        bias.add(k, r, 1.0 / (2.0 * variance));
      });
    }
  }
  const BiasEstimate solved = bias.solve();
  estimate.remaining_inverse_depth_bias_per_m = solved.bias_per_m;
  estimate.remaining_inverse_depth_bias_sigma_per_m = solved.sigma_per_m;
  return estimate;
}

}  // namespace vifusion::calib
