#pragma once
// OpenCV's cv::rgbd::RgbdICPOdometry, frame to frame, on the benchmark's frames: the side-by-side
// baseline of bench_rgbd_slam (speed and ATE).

#include <limits>
#include <string>

#include "vifusion/preprocess/kernel_params.hpp"
#include "bench_sequence.hpp"

namespace vifusion::bench {

struct OpenCvRun {
  double ms_per_frame = 0.0;  ///< mean wall time of compute() over frames 1 … n−1
  double ate_m = std::numeric_limits<double>::quiet_NaN();
  int failed_frames = 0;  ///< compute() returned false: the pose is carried over unchanged
};

/// Same intrinsics and depth gate as our preprocessing; every other parameter at OpenCV 4.6's
/// defaults: max depth difference 0.07 m, max points part 0.07, iterations {7, 7, 7, 10} (finest
/// level first, 4 levels), min gradient magnitudes 10 at every level, rigid-body motion, and a
/// failed compute() when the motion exceeds 0.15 m or 15°. Depth is CV_32F metres with NaN where
/// invalid, intensity 8-bit grey (as the opencv_contrib odometry sample); both are converted before
/// timing. OpenCV's own thread pool (cv::getNumThreads()) runs its parallel loops.
/// With --trajectory_dir the estimate is written as <name>.txt.
OpenCvRun runOpenCv(const Sequence& sequence, const preprocess::DepthToMetricParams& gate, const std::string& name);

}  // namespace vifusion::bench
