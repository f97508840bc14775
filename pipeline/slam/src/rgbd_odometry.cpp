#include "vifusion/slam/rgbd_odometry.hpp"

#include <chrono>

#include "vifusion/core/error.hpp"

namespace vifusion::slam {
namespace {

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

RgbdOdometry::RgbdOdometry(gpu::GpuContext& context, const RigCalibration& calibration, const TrackerOptions& options) {
  tracker_ = std::make_unique<DenseTracker>(context, plan_, calibration.camera, calibration.depth_scale_m, options);
  arena_ = gpu::MemoryArena::create(context, plan_);
  tracker_->build(*arena_);
}

RgbdOdometry::~RgbdOdometry() = default;

FrameResult RgbdOdometry::process(const RgbdFrame& frame) {
  FrameResult result;
  result.t_ns = frame.t_ns;
  const auto start = std::chrono::steady_clock::now();
  tracker_->preprocess(frame);
  result.preprocess_ms = msSince(start);

  if (first_frame_) {
    first_frame_ = false;
    tracker_->setReferenceToCurrent();
    return result;  // the first camera frame defines W
  }
  const auto track_start = std::chrono::steady_clock::now();
  const TrackingResult tracking = tracker_->track(T_previous_current_);
  result.tracking_ms = msSince(track_start);
  result.lost = tracking.lost;
  result.icp_inliers = tracking.icp_inliers;
  result.rgb_inliers = tracking.rgb_inliers;
  result.iterations = tracking.iterations;
  // A lost frame keeps the constant-velocity prediction and still becomes the reference, so that
  // tracking can resume from the next frame instead of comparing ever more distant views.
  T_previous_current_ = tracking.T_ref_cur;
  T_W_previous_ = T_W_previous_ * tracking.T_ref_cur;
  tracker_->setReferenceToCurrent();
  result.T_W_C = T_W_previous_;
  return result;
}

}  // namespace vifusion::slam
