#include "closure_judge.hpp"

#include <algorithm>
#include <cstdlib>
#include <iterator>

namespace vifusion::cli {

ClosureJudge::ClosureJudge(std::span<const datasets::StampedPose> ground_truth) {
  if (ground_truth.empty()) return;
  const SE3d T_W_world = ground_truth.front().T_world_body.inverse();
  for (const datasets::StampedPose& pose : ground_truth) T_W_C_true_[pose.t_ns] = T_W_world * pose.T_world_body;
}

void ClosureJudge::add(const slam::FrameResult& result) {
  if (result.closure.outcome != slam::ClosureOutcome::kAccepted) return;
  // Nearest ground-truth stamp, within kMaxStampGapNs.
  auto truth = T_W_C_true_.lower_bound(result.t_ns);
  if (truth != T_W_C_true_.begin() &&
      (truth == T_W_C_true_.end() || truth->first - result.t_ns > result.t_ns - std::prev(truth)->first)) {
    truth = std::prev(truth);
  }
  if (truth == T_W_C_true_.end() || std::abs(truth->first - result.t_ns) > kMaxStampGapNs) {
    ++not_judged_;
    return;
  }
  const SE3d T_W_C_before = result.closure.T_Wnew_Wold.inverse() * result.T_W_C;
  const double before_m = (T_W_C_before.translation() - truth->second.translation()).norm();
  const double after_m = (result.T_W_C.translation() - truth->second.translation()).norm();
  const double increase_m = after_m - before_m;
  ++judged_;
  if (increase_m > kFalseClosureSigmas * result.closure.registration.far_sigma_m) ++false_;
  worst_increase_m_ = any_judged_ ? std::max(worst_increase_m_, increase_m) : increase_m;
  any_judged_ = true;
}

nlohmann::json ClosureJudge::json() const {
  return {{"judged", judged_},
          {"false", false_},
          {"not_judged", not_judged_},
          {"worst_error_increase_mm", 1e3 * worst_increase_m_}};
}

}  // namespace vifusion::cli
