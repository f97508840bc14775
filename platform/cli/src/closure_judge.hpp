#pragma once
// Judges each accepted loop closure of a `vifusion run` against the dataset's ground truth, so that false
// closures are counted, not guessed (issue 16: "no false closure accepted on any sim: preset").
//
// W is the first camera frame, so the true pose of frame k in W is T_gt(0)⁻¹·T_gt(k). A closure corrects the
// current camera pose; it is false when that correction moves the pose's position away from the truth by more
// than kFalseClosureSigmas times the registration's own σ_p at the far end of the depth range
// (RegistrationResult::far_sigma_m, what the covariance test accepted): a right closure may still leave some
// error, a wrong one adds error it did not know it had. Without ground truth at a closure's stamp (none in the
// dataset, or not at that time) the closure is counted as not judged.

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <span>

#include "vifusion/core/se3.hpp"
#include "vifusion/datasets/dataset_reader.hpp"
#include "vifusion/slam/slam.hpp"

namespace vifusion::cli {

class ClosureJudge {
 public:
  /// One-sided 3σ: a right closure moves the pose away from the truth by more than this with probability ≈ 0.1 %.
  static constexpr double kFalseClosureSigmas = 3.0;

  /// A frame's ground truth is the pose stamped within this of it: datasets store both from one clock, to the
  /// microsecond in text files [ns].
  static constexpr std::int64_t kMaxStampGapNs = 1'000'000;

  explicit ClosureJudge(std::span<const datasets::StampedPose> ground_truth);

  /// A frame's result; only accepted closures are judged.
  void add(const slam::FrameResult& result);

  /// {"judged": N, "false": F, "not_judged": M, "worst_error_increase_mm": X (largest after − before, may be < 0)}
  nlohmann::json json() const;

 private:
  std::map<std::int64_t, SE3d> T_W_C_true_;  ///< ground truth by stamp, in W (the first frame's camera)
  int judged_ = 0;
  int false_ = 0;
  int not_judged_ = 0;
  double worst_increase_m_ = 0.0;
  bool any_judged_ = false;
};

}  // namespace vifusion::cli
