#pragma once
// A straight line y = intercept + slope·x through noisy points with outliers: how the sync analysis turns
// offsets over time into a drift (the slope) and jitter (the residuals).
//
// ESTIMATOR: Theil–Sen for the start, then IRLS with Tukey's biweight.
// - Timing residuals are mostly Gaussian (interrupt and USB jitter) with a few far-off stamps (a frame
//   stamped by the kernel when its event was late, a scheduling stall). Least squares lets each outlier
//   pull the line; Huber's weights bound that pull but never remove it (5 % outliers at 5 ms still bias
//   the offset by tens of µs). Tukey's biweight gives points beyond c·scale weight 0: far outliers
//   change nothing, and at c = 4.685 it keeps 95 % of least squares' efficiency on Gaussian noise,
//   which the 20 µs offset accuracy over a 60 s run needs (least squares' own error is ~7 µs there).
// - Tukey's loss is not convex, so IRLS needs a start that is already robust: Theil–Sen (the median of
//   pairwise slopes; breakdown 29 %) on at most kTheilSenMaxPoints points spread evenly over the input,
//   so its O(m²) cost stays bounded for long runs. The scale is 1.4826·MAD of the residuals, re-estimated
//   after each IRLS convergence until it settles (a start with a poor slope inflates the first MAD).
// Exact data (MAD 0) returns the Theil–Sen line. Fewer than two distinct x: slope NaN, intercept the
// median of y.

#include <cstddef>
#include <limits>
#include <span>

namespace vifusion::synccheck {

struct LineFit {
  double intercept = std::numeric_limits<double>::quiet_NaN();  ///< y at x = 0
  double slope = std::numeric_limits<double>::quiet_NaN();      ///< dy/dx
  double scale = std::numeric_limits<double>::quiet_NaN();      ///< 1.4826·MAD of the residuals
  std::size_t inliers = 0;                                      ///< points with a non-zero final weight
  int iterations = 0;                                           ///< IRLS steps taken, all rounds

  bool valid() const;  ///< intercept and slope are finite
  double at(double x) const { return intercept + slope * x; }
};

/// Tukey biweight tuning constant [scale units]: 95 % Gaussian efficiency.
inline constexpr double kTukeyC = 4.685;
/// Points the Theil–Sen start uses at most (m²/2 slopes: 512 → 131 k).
inline constexpr std::size_t kTheilSenMaxPoints = 512;

/// Fits y over x (same length; finite values). Throws nothing; degenerate input gives NaN fields.
LineFit fitRobustLine(std::span<const double> x, std::span<const double> y);

}  // namespace vifusion::synccheck
