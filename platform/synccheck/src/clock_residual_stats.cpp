#include "clock_residual_stats.hpp"

#include <cmath>
#include <vector>

#include "sample_stats.hpp"

namespace vifusion::synccheck {
namespace {

constexpr double kResidualQuantile = 0.99;

}  // namespace

ClockResidualStats measureClockResiduals(std::span<const ClockResidualSample> residuals, ProblemLog& problems) {
  ClockResidualStats stats;
  std::vector<double> finite_ns;
  finite_ns.reserve(residuals.size());
  for (std::size_t i = 0; i < residuals.size(); ++i) {
    if (std::isfinite(residuals[i].residual_ns)) {
      finite_ns.push_back(residuals[i].residual_ns);
    } else {
      ++stats.non_finite;
      problems.note("clock residual %zu (t_ns %lld): residual_ns is %g", i, static_cast<long long>(residuals[i].t_ns),
                    residuals[i].residual_ns);
    }
  }
  stats.samples = finite_ns.size();
  if (finite_ns.empty()) return stats;
  stats.mean_ns = mean(finite_ns);
  stats.std_ns = sampleStd(finite_ns);
  stats.max_abs_ns = maxAbs(finite_ns);
  for (double& r : finite_ns) r = std::abs(r);
  stats.p99_abs_ns = quantile(std::move(finite_ns), kResidualQuantile);
  return stats;
}

}  // namespace vifusion::synccheck
