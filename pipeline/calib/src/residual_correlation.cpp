#include "vifusion/calib/residual_correlation.hpp"

#include <cmath>
#include <stdexcept>

namespace vifusion::calib {
namespace {

constexpr int kLargestMaxLag_px = 32;

}  // namespace

ResidualCorrelation::ResidualCorrelation(int max_lag_px) : max_lag_px_(max_lag_px) {
  if (max_lag_px < 1 || max_lag_px > kLargestMaxLag_px) {
    throw std::invalid_argument("residual correlation: max_lag must be in [1, 32] px");
  }
  const std::size_t lags = static_cast<std::size_t>(2 * max_lag_px + 1) * static_cast<std::size_t>(max_lag_px + 1);
  product_sum_.assign(lags, 0.0);
  count_.assign(lags, 0);
}

std::size_t ResidualCorrelation::index(int dx, int dy) const {
  return static_cast<std::size_t>(dy) * static_cast<std::size_t>(2 * max_lag_px_ + 1) +
         static_cast<std::size_t>(dx + max_lag_px_);
}

void ResidualCorrelation::add(ImageView<const float> x) {
  for (int dy = 0; dy <= max_lag_px_; ++dy) {
    for (int dx = dy == 0 ? 0 : -max_lag_px_; dx <= max_lag_px_; ++dx) {
      double sum = 0.0;
      std::int64_t count = 0;
      for (int y = 0; y + dy < x.height; ++y) {
        for (int u = std::max(0, -dx); u < x.width && u + dx < x.width; ++u) {
          const float a = x(u, y);
          const float b = x(u + dx, y + dy);
          if (std::isnan(a) || std::isnan(b)) continue;
          sum += static_cast<double>(a) * b;
          ++count;
        }
      }
      product_sum_[index(dx, dy)] += sum;
      count_[index(dx, dy)] += count;
    }
  }
}

double ResidualCorrelation::correlation(int dx, int dy) const {
  if (dy < 0 || (dy == 0 && dx < 0)) return correlation(-dx, -dy);
  const std::size_t zero = index(0, 0);
  const std::size_t lag = index(dx, dy);
  if (count_[zero] == 0 || count_[lag] == 0 || product_sum_[zero] <= 0.0) return 0.0;
  const double variance = product_sum_[zero] / static_cast<double>(count_[zero]);
  return product_sum_[lag] / static_cast<double>(count_[lag]) / variance;
}

double ResidualCorrelation::pixelsPerSample() const {
  double sum = 0.0;
  for (int dy = -max_lag_px_; dy <= max_lag_px_; ++dy) {
    for (int dx = -max_lag_px_; dx <= max_lag_px_; ++dx) sum += correlation(dx, dy);
  }
  return std::max(1.0, sum);
}

double ResidualCorrelation::correlationLength_px() const {
  const double threshold = std::exp(-1.0);
  double previous = 1.0;
  for (int lag = 1; lag <= max_lag_px_; ++lag) {
    const double rho = 0.5 * (correlation(lag, 0) + correlation(0, lag));
    if (rho <= threshold) return lag - 1 + (previous - threshold) / (previous - rho);
    previous = rho;
  }
  return max_lag_px_;
}

}  // namespace vifusion::calib
