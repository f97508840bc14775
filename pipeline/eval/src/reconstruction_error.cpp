#include "vifusion/eval/reconstruction_error.hpp"

#include <algorithm>
#include <cmath>

#include "vifusion/core/error.hpp"

namespace vifusion::eval {

ReconstructionError reconstructionError(const std::vector<Eigen::Vector3d>& points_est, const SE3d& T_gt_est,
                                        const std::function<double(const Eigen::Vector3d&)>& distance_m) {
  if (points_est.empty()) throw Error("reconstruction error: the map has no points");
  std::vector<double> distances;
  distances.reserve(points_est.size());
  ReconstructionError result;
  double sum = 0.0;
  double sum_sq = 0.0;
  std::size_t close = 0;
  for (const Eigen::Vector3d& p_est : points_est) {
    const double d = distance_m(T_gt_est * p_est);
    distances.push_back(d);
    sum += d;
    sum_sq += d * d;
    if (d < 0.01) ++close;
  }
  const double n = static_cast<double>(distances.size());
  const auto middle = distances.begin() + static_cast<std::ptrdiff_t>(distances.size() / 2);
  std::nth_element(distances.begin(), middle, distances.end());
  result.mean_m = sum / n;
  result.median_m = *middle;
  result.rms_m = std::sqrt(sum_sq / n);
  result.within_1cm = static_cast<double>(close) / n;
  result.points = distances.size();
  return result;
}

}  // namespace vifusion::eval
