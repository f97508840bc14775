#include "vifusion/eval/camera_tilt.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>

#include "vifusion/core/error.hpp"

namespace vifusion::eval {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

Eigen::Vector3d direction(const Eigen::Vector3d& g, const char* what) {
  const double norm = g.norm();
  if (!std::isfinite(norm) || norm == 0.0) throw Error(std::string("camera tilt: ") + what + " is zero or not finite");
  return g / norm;
}

}  // namespace

CameraTilt cameraTilt(const std::vector<StampedPose>& gt, const std::vector<StampedPose>& est,
                      const std::vector<std::size_t>& gt_index, const std::vector<std::size_t>& est_index,
                      const std::vector<EstimatedState>& states, const Eigen::Vector3d& g_gt_W,
                      std::int64_t max_difference_ns) {
  const Eigen::Vector3d down_G = direction(g_gt_W, "the ground truth's gravity");
  const auto earlier = [](const EstimatedState& s, std::int64_t t_ns) { return s.t_ns < t_ns; };
  CameraTilt tilt;
  std::vector<CameraTiltSample>& samples = tilt.series;
  const std::size_t pairs = std::min(gt_index.size(), est_index.size());
  for (std::size_t i = 0; i < pairs; ++i) {
    const StampedPose& e = est.at(est_index[i]);
    const StampedPose& g = gt.at(gt_index[i]);
    // The nearest state in time: the one at or after the stamp, or the one before it.
    const auto after = std::lower_bound(states.begin(), states.end(), e.t_ns, earlier);
    const EstimatedState* nearest = nullptr;
    if (after != states.end()) nearest = &*after;
    if (after != states.begin() && (nearest == nullptr || e.t_ns - (after - 1)->t_ns < nearest->t_ns - e.t_ns)) {
      nearest = &*(after - 1);
    }
    if (nearest == nullptr || std::llabs(nearest->t_ns - e.t_ns) > max_difference_ns) continue;
    const Eigen::Vector3d down_C_est =
        e.T_world_body.rotationMatrix().transpose() * direction(nearest->g_W, "an estimated gravity");
    const Eigen::Vector3d down_C_gt = g.T_world_body.rotationMatrix().transpose() * down_G;
    const double cos_angle = std::clamp(down_C_est.dot(down_C_gt), -1.0, 1.0);
    samples.push_back({e.t_ns, std::acos(cos_angle) * kRadToDeg});
  }
  if (samples.empty()) throw Error("camera tilt: no estimated pose has an estimator state at its stamp");
  double sum_deg2 = 0.0;
  for (const CameraTiltSample& sample : samples) {
    sum_deg2 += sample.tilt_deg * sample.tilt_deg;
    tilt.max_deg = std::max(tilt.max_deg, sample.tilt_deg);
  }
  tilt.rms_deg = std::sqrt(sum_deg2 / static_cast<double>(samples.size()));
  tilt.final_deg = samples.back().tilt_deg;
  return tilt;
}

}  // namespace vifusion::eval
