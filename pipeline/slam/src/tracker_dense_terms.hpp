#pragma once
// The dense tracker as the two-state estimator's dense terms: evaluates the GPU terms at a camera pose in
// W against the reference view rendered at T_W_ref and hands them over in the state's coordinates.
// Unlike DenseTracker::track(), a rank-deficient dense system is usable here (a blank wall leaves the
// sliding directions to the IMU); only an evaluation with almost no inliers is refused. Before they are
// handed over, the ICP's directions that its surfaces do not constrain are removed at every level
// (icp_degeneracy.hpp: the IMU carries them, not quantisation bands that move with the camera) and the
// information is scaled for the pixels' correlation (DenseTermsOptions).

#include "vifusion/estimator/two_state_estimator.hpp"
#include "vifusion/slam/dense_terms_options.hpp"
#include "vifusion/slam/dense_tracker.hpp"

namespace vifusion::slam {

class TrackerDenseTerms : public estimator::DenseTerms {
 public:
  TrackerDenseTerms(DenseTracker& tracker, const DenseTermsOptions& options) : tracker_(tracker), options_(options) {}

  /// The pose the reference view (the map prediction) was rendered at; set before each frame. Clears the
  /// statistics: a frame whose solve ends before level 0 reports none.
  void setReference(const SE3d& T_W_ref) {
    T_W_ref_ = T_W_ref;
    statistics_ = TrackingResult{};
  }
  /// Inlier statistics of this frame's last level-0 evaluation (zero if there was none).
  const TrackingResult& statistics() const { return statistics_; }

  int levels() const override { return tracker_.options().levels; }
  bool evaluate(int level, const SE3d& T_W_C, estimator::PoseSystem& system) override;
  bool healthy() const override { return tracker_.healthy(statistics_); }

 private:
  DenseTracker& tracker_;
  DenseTermsOptions options_;
  SE3d T_W_ref_;
  TrackingResult statistics_;
};

}  // namespace vifusion::slam
