#include "stream_stats.hpp"

#include <cmath>
#include <utility>

#include "sample_stats.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion::synccheck {
namespace {

constexpr double kJitterQuantile = 0.99;
constexpr double kNsPerSecondPerPpm = 1'000.0;  // a slope of 1 ns/s is 1e-3 ppm
constexpr std::size_t kLineParameters = 2;      // the residuals' lost degrees of freedom

}  // namespace

StreamStats measureStream(std::string name, std::vector<std::int64_t> t_ns, std::vector<double> offset_ns) {
  StreamStats stats;
  stats.name = std::move(name);
  stats.count = offset_ns.size();
  stats.t_ns = std::move(t_ns);
  stats.offset_ns = std::move(offset_ns);
  if (stats.count == 0) return stats;
  stats.offset_mean_ns = mean(stats.offset_ns);
  stats.offset_median_ns = median(stats.offset_ns);
  stats.first_t_ns = stats.t_ns.front();

  std::vector<double> x_s(stats.count);
  for (std::size_t i = 0; i < stats.count; ++i) x_s[i] = nsToSeconds(stats.t_ns[i] - stats.first_t_ns);
  stats.fit = fitRobustLine(x_s, stats.offset_ns);
  if (!stats.fit.valid()) return stats;
  stats.offset_at_first_ns = stats.fit.at(0.0);
  stats.drift_ppm = stats.fit.slope / kNsPerSecondPerPpm;

  std::vector<double> residual_ns(stats.count);
  double sum_squares = 0.0;
  for (std::size_t i = 0; i < stats.count; ++i) {
    residual_ns[i] = stats.offset_ns[i] - stats.fit.at(x_s[i]);
    sum_squares += residual_ns[i] * residual_ns[i];
  }
  if (stats.count > kLineParameters) {
    stats.jitter_std_ns = std::sqrt(sum_squares / static_cast<double>(stats.count - kLineParameters));
  }
  stats.jitter_max_ns = maxAbs(residual_ns);
  for (double& r : residual_ns) r = std::abs(r);
  stats.jitter_p99_ns = quantile(std::move(residual_ns), kJitterQuantile);
  return stats;
}

}  // namespace vifusion::synccheck
