#include "sample_stats.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vifusion::synccheck {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

double median(std::vector<double> values) { return quantile(std::move(values), 0.5); }

double quantile(std::vector<double> values, double fraction) {
  if (values.empty()) return kNaN;
  const double position = std::clamp(fraction, 0.0, 1.0) * static_cast<double>(values.size() - 1);
  const auto lower = static_cast<std::size_t>(std::floor(position));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(lower), values.end());
  const double lower_value = values[lower];
  if (lower + 1 >= values.size()) return lower_value;
  // The next order statistic is the smallest of the values above the lower one.
  const double upper_value = *std::min_element(values.begin() + static_cast<std::ptrdiff_t>(lower) + 1, values.end());
  return lower_value + (position - static_cast<double>(lower)) * (upper_value - lower_value);
}

double mean(std::span<const double> values) {
  if (values.empty()) return kNaN;
  double sum = 0.0;
  for (double value : values) sum += value;
  return sum / static_cast<double>(values.size());
}

double sampleStd(std::span<const double> values) {
  if (values.size() < 2) return kNaN;
  const double centre = mean(values);
  double sum_squares = 0.0;
  for (double value : values) sum_squares += (value - centre) * (value - centre);
  return std::sqrt(sum_squares / static_cast<double>(values.size() - 1));
}

double maxAbs(std::span<const double> values) {
  if (values.empty()) return kNaN;
  double largest = 0.0;
  for (double value : values) largest = std::max(largest, std::abs(value));
  return largest;
}

}  // namespace vifusion::synccheck
