#include "vifusion/synccheck/robust_line_fit.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "sample_stats.hpp"

namespace vifusion::synccheck {
namespace {

constexpr double kMadToSigma = 1.4826;  // a Gaussian's median absolute deviation × this = its σ
constexpr int kMaxIrlsIterations = 50;  // Tukey IRLS converges in ~5–10 steps from a robust start
constexpr int kMaxScaleRounds = 5;      // scale re-estimates; the second usually settles it
// IRLS stops when the line moves less than this many scales anywhere over the x range.
constexpr double kConvergenceScales = 1e-9;
constexpr double kScaleSettledFraction = 0.01;  // a re-estimated scale within 1 % ends the rounds

std::vector<double> residuals(std::span<const double> x, std::span<const double> y, const LineFit& line) {
  std::vector<double> r(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) r[i] = y[i] - line.at(x[i]);
  return r;
}

double residualScale(std::span<const double> x, std::span<const double> y, const LineFit& line) {
  std::vector<double> r = residuals(x, y, line);
  for (double& value : r) value = std::abs(value);
  return kMadToSigma * median(std::move(r));
}

/// Theil–Sen on up to kTheilSenMaxPoints points spread evenly over the input (both ends included).
LineFit theilSen(std::span<const double> x, std::span<const double> y) {
  const std::size_t n = x.size();
  const std::size_t m = std::min(n, kTheilSenMaxPoints);
  std::vector<std::size_t> picked(m);
  for (std::size_t k = 0; k < m; ++k) picked[k] = m == 1 ? 0 : k * (n - 1) / (m - 1);
  std::vector<double> slopes;
  slopes.reserve(m * (m - 1) / 2);
  for (std::size_t a = 0; a < m; ++a) {
    for (std::size_t b = a + 1; b < m; ++b) {
      const double dx = x[picked[b]] - x[picked[a]];
      if (dx != 0.0) slopes.push_back((y[picked[b]] - y[picked[a]]) / dx);
    }
  }
  LineFit fit;
  if (slopes.empty()) {  // one distinct x: a level, no slope
    fit.intercept = median(std::vector<double>(y.begin(), y.end()));
    return fit;
  }
  fit.slope = median(std::move(slopes));
  std::vector<double> intercepts(n);
  for (std::size_t i = 0; i < n; ++i) intercepts[i] = y[i] - fit.slope * x[i];
  fit.intercept = median(std::move(intercepts));
  return fit;
}

double tukeyWeight(double residual, double scale) {
  const double u = residual / (kTukeyC * scale);
  if (std::abs(u) >= 1.0) return 0.0;
  const double v = 1.0 - u * u;
  return v * v;
}

/// IRLS with Tukey weights at a fixed `scale`, from `fit`; returns the steps taken.
int irls(std::span<const double> x, std::span<const double> y, double scale, LineFit& fit) {
  const auto [x_min, x_max] = std::minmax_element(x.begin(), x.end());
  const double x_span = *x_max - *x_min;
  for (int step = 1; step <= kMaxIrlsIterations; ++step) {
    double sw = 0.0, swx = 0.0, swy = 0.0;
    std::vector<double> w(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
      w[i] = tukeyWeight(y[i] - fit.at(x[i]), scale);
      sw += w[i], swx += w[i] * x[i], swy += w[i] * y[i];
    }
    if (sw <= 0.0) return step;
    const double x_mean = swx / sw, y_mean = swy / sw;  // centred sums: no cancellation
    double sxx = 0.0, sxy = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      sxx += w[i] * (x[i] - x_mean) * (x[i] - x_mean);
      sxy += w[i] * (x[i] - x_mean) * (y[i] - y_mean);
    }
    if (sxx <= 0.0) return step;  // the weighted points share one x: keep the line we have
    const double slope = sxy / sxx;
    const double intercept = y_mean - slope * x_mean;
    const double moved = std::abs(intercept - fit.intercept) + std::abs(slope - fit.slope) * x_span;
    fit.slope = slope;
    fit.intercept = intercept;
    if (moved <= kConvergenceScales * scale) return step;
  }
  return kMaxIrlsIterations;
}

}  // namespace

bool LineFit::valid() const { return std::isfinite(intercept) && std::isfinite(slope); }

LineFit fitRobustLine(std::span<const double> x, std::span<const double> y) {
  if (x.empty() || x.size() != y.size()) return {};
  LineFit fit = theilSen(x, y);
  if (!fit.valid()) return fit;
  double last_scale = 0.0;
  for (int round = 0; round < kMaxScaleRounds; ++round) {
    const double scale = residualScale(x, y, fit);
    fit.scale = scale;
    if (scale <= 0.0) break;  // more than half the points on the line exactly: it is the line
    if (round > 0 && std::abs(scale - last_scale) <= kScaleSettledFraction * last_scale) break;
    fit.iterations += irls(x, y, scale, fit);
    last_scale = scale;
  }
  fit.inliers = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double r = std::abs(y[i] - fit.at(x[i]));
    if (fit.scale > 0.0 ? r < kTukeyC * fit.scale : r == 0.0) ++fit.inliers;
  }
  return fit;
}

}  // namespace vifusion::synccheck
