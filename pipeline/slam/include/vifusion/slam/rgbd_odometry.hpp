#pragma once
// RGB-D mode of the pipeline as it stands: every frame is tracked against the previous one by the
// dense tracker (frame-to-frame odometry) and chained into T_W_C, W being the first camera frame
// (DESIGN §3). The surfel map will replace the previous frame as the reference view.

#include <cstdint>
#include <memory>

#include "vifusion/core/rig_calibration.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/core/sensor_data.hpp"
#include "vifusion/gpu/gpu_context.hpp"
#include "vifusion/gpu/memory_arena.hpp"
#include "vifusion/slam/dense_tracker.hpp"

namespace vifusion::slam {

struct FrameResult {
  int64_t t_ns = 0;
  SE3d T_W_C;                 ///< camera pose in the map world (first camera frame)
  bool lost = false;          ///< tracking failed: the pose is the constant-velocity prediction
  double icp_inliers = 0.0;
  double rgb_inliers = 0.0;
  int iterations = 0;
  double preprocess_ms = 0.0;  ///< wall time of upload + preprocessing
  double tracking_ms = 0.0;    ///< wall time of all Gauss-Newton iterations
};

class RgbdOdometry {
 public:
  /// Sizes every GPU buffer for the calibration's camera and allocates the arena once.
  RgbdOdometry(gpu::GpuContext& context, const RigCalibration& calibration, const TrackerOptions& options);
  ~RgbdOdometry();

  FrameResult process(const RgbdFrame& frame);
  uint64_t arenaBytes() const { return arena_->allocatedBytes(); }

 private:
  gpu::CapacityPlan plan_;
  std::unique_ptr<DenseTracker> tracker_;
  std::unique_ptr<gpu::MemoryArena> arena_;
  bool first_frame_ = true;
  SE3d T_W_previous_;
  SE3d T_previous_current_;  ///< last frame-to-frame motion: the constant-velocity guess
};

}  // namespace vifusion::slam
