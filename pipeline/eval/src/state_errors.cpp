#include "vifusion/eval/state_errors.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion::eval {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

double rms(const std::vector<double>& values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  double sum = 0.0;
  for (double v : values) sum += v * v;
  return std::sqrt(sum / static_cast<double>(values.size()));
}

double maxOf(const std::vector<double>& values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  return *std::max_element(values.begin(), values.end());
}

}  // namespace

StateErrors stateErrors(const std::vector<GroundTruthState>& gt, const std::vector<EstimatedState>& est,
                        const Eigen::Matrix3d& R_gt_est, const Eigen::Vector3d& g_gt_W) {
  StateErrors errors;
  const auto later = [](const GroundTruthState& s, int64_t t_ns) { return s.t_ns < t_ns; };
  for (const EstimatedState& e : est) {
    const auto upper = std::lower_bound(gt.begin(), gt.end(), e.t_ns, later);
    if (upper == gt.end() || (upper == gt.begin() && upper->t_ns != e.t_ns)) continue;  // outside the span
    const GroundTruthState& b = *upper;
    const GroundTruthState& a = upper == gt.begin() ? b : *(upper - 1);
    const double s = b.t_ns == a.t_ns ? 0.0 : static_cast<double>(e.t_ns - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns);
    const Eigen::Vector3d v_gt = (1.0 - s) * a.v_W_S + s * b.v_W_S;
    const Eigen::Vector3d b_g_gt = (1.0 - s) * a.b_g + s * b.b_g;
    const Eigen::Vector3d b_a_gt = (1.0 - s) * a.b_a + s * b.b_a;
    const Eigen::Vector3d g_est = R_gt_est * e.g_W;
    const double cos_angle = std::clamp(g_est.normalized().dot(g_gt_W.normalized()), -1.0, 1.0);
    errors.series.push_back({e.t_ns, (R_gt_est * e.v_W_S - v_gt).norm(), (e.b_g - b_g_gt).norm(),
                             (e.b_a - b_a_gt).norm(), std::acos(cos_angle) * kRadToDeg});
  }
  if (errors.series.empty()) throw Error("state errors: no estimated state lies within the ground truth's time span");

  const int64_t t0_ns = errors.series.front().t_ns;
  std::vector<double> velocity, velocity_late, gyro_late, accel_late, gravity;
  for (const StateErrorSample& sample : errors.series) {
    const double t_s = nsToSeconds(sample.t_ns - t0_ns);
    velocity.push_back(sample.velocity_mps);
    gravity.push_back(sample.gravity_deg);
    if (t_s >= 5.0) velocity_late.push_back(sample.velocity_mps);
    if (t_s >= 15.0) {
      gyro_late.push_back(sample.gyro_bias_rad_s);
      accel_late.push_back(sample.accel_bias_mps2);
    }
  }
  errors.velocity_rms_mps = rms(velocity);
  errors.velocity_rms_after_5s_mps = rms(velocity_late);
  errors.gyro_bias_max_after_15s = maxOf(gyro_late);
  errors.accel_bias_max_after_15s = maxOf(accel_late);
  errors.gyro_bias_final_rad_s = errors.series.back().gyro_bias_rad_s;
  errors.accel_bias_final_mps2 = errors.series.back().accel_bias_mps2;
  errors.gravity_rms_deg = rms(gravity);
  errors.gravity_final_deg = errors.series.back().gravity_deg;
  return errors;
}

}  // namespace vifusion::eval
