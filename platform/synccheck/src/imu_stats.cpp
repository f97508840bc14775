#include "imu_stats.hpp"

#include <algorithm>
#include <vector>

#include "sample_stats.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion::synccheck {

ImuStats measureImu(std::span<const std::int64_t> imu_t_ns, ProblemLog& problems) {
  ImuStats stats;
  stats.samples = imu_t_ns.size();
  if (imu_t_ns.size() < 2) return stats;
  std::vector<double> positive_dt_ns;
  positive_dt_ns.reserve(imu_t_ns.size() - 1);
  std::int64_t largest_dt_ns = 0;
  for (std::size_t i = 1; i < imu_t_ns.size(); ++i) {
    const std::int64_t dt_ns = imu_t_ns[i] - imu_t_ns[i - 1];
    if (dt_ns <= 0) {
      ++stats.out_of_order;
      problems.note("IMU sample %zu: time %s by %lld ns", i, dt_ns == 0 ? "repeats" : "goes backwards",
                    static_cast<long long>(-dt_ns));
      continue;
    }
    positive_dt_ns.push_back(static_cast<double>(dt_ns));
    largest_dt_ns = std::max(largest_dt_ns, dt_ns);
  }
  if (positive_dt_ns.empty()) return stats;
  stats.largest_gap_ns = static_cast<double>(largest_dt_ns);
  // 1/dt is monotone, so the median of the rates is the rate of the median interval.
  stats.median_dt_ns = median(positive_dt_ns);
  stats.rate_hz = static_cast<double>(kNsPerSecond) / stats.median_dt_ns;
  const double gap_ns = kImuGapFactor * stats.median_dt_ns;
  stats.gaps = static_cast<std::size_t>(
      std::count_if(positive_dt_ns.begin(), positive_dt_ns.end(), [&](double dt) { return dt > gap_ns; }));
  const auto [first, last] = std::minmax_element(imu_t_ns.begin(), imu_t_ns.end());
  if (*last > *first) {
    stats.mean_rate_hz = static_cast<double>(imu_t_ns.size() - 1) / nsToSeconds(*last - *first);
  }
  return stats;
}

}  // namespace vifusion::synccheck
