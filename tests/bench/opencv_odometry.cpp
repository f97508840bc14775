#include "opencv_odometry.hpp"

#include <Eigen/Geometry>
#include <chrono>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/rgbd/depth.hpp>
#include <vector>

#include "vifusion/eval/metrics.hpp"
#include "timing.hpp"

namespace vifusion::bench {
namespace {

SE3d se3FromCv(const cv::Mat& Rt) {
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) R(r, c) = Rt.at<double>(r, c);
    t(r) = Rt.at<double>(r, 3);
  }
  return SE3d(Eigen::Quaterniond(R), t);
}

}  // namespace

OpenCvRun runOpenCv(const Sequence& sequence, const preprocess::DepthToMetricParams& gate, const std::string& name) {
  const PinholeCamera& camera = sequence.calibration.camera;
  const cv::Mat K = (cv::Mat_<float>(3, 3) << static_cast<float>(camera.fx), 0.f, static_cast<float>(camera.cx), 0.f,
                     static_cast<float>(camera.fy), static_cast<float>(camera.cy), 0.f, 0.f, 1.f);
  const cv::Ptr<cv::rgbd::RgbdICPOdometry> odometry =
      cv::rgbd::RgbdICPOdometry::create(K, gate.min_depth_m, gate.max_depth_m);

  std::vector<cv::Mat> depth_m, grey;
  for (const RgbdFrame& frame : sequence.frames) {
    const cv::Mat raw(frame.depth.height(), frame.depth.width(), CV_16UC1, const_cast<uint16_t*>(frame.depth.data()));
    cv::Mat depth;
    raw.convertTo(depth, CV_32FC1, frame.depth_scale_m);
    depth.setTo(std::numeric_limits<float>::quiet_NaN(), raw == 0);
    depth_m.push_back(depth);
    const cv::Mat rgb(frame.rgb.height(), frame.rgb.width(), CV_8UC3, const_cast<Rgb8*>(frame.rgb.data()));
    cv::Mat g;
    cv::cvtColor(rgb, g, cv::COLOR_RGB2GRAY);
    grey.push_back(g);
  }
  const auto frameAt = [&](std::size_t i) {
    return cv::makePtr<cv::rgbd::OdometryFrame>(grey[i], depth_m[i], cv::Mat(), cv::Mat(), static_cast<int>(i));
  };
  {  // warm-up (thread pool, first allocations), not timed
    cv::Ptr<cv::rgbd::OdometryFrame> src = frameAt(1), dst = frameAt(0);
    cv::Mat Rt;
    odometry->compute(src, dst, Rt);
  }

  // compute(current, previous) gives Rt = T_previous_current (p_previous = Rt · p_current); each
  // frame's pyramids are built once, as the source, and completed as the destination next time.
  OpenCvRun run;
  std::vector<eval::StampedPose> trajectory = {{sequence.frames[0].t_ns, SE3d()}};
  cv::Ptr<cv::rgbd::OdometryFrame> previous = frameAt(0);
  double total_ms = 0.0;
  for (std::size_t i = 1; i < sequence.frames.size(); ++i) {
    cv::Ptr<cv::rgbd::OdometryFrame> current = frameAt(i);
    cv::Mat Rt;
    const auto start = std::chrono::steady_clock::now();
    const bool ok = odometry->compute(current, previous, Rt);
    total_ms += msSince(start);
    SE3d T_W_C = trajectory.back().T_world_body;
    if (ok) {
      T_W_C = T_W_C * se3FromCv(Rt);
    } else {
      ++run.failed_frames;
    }
    trajectory.push_back({sequence.frames[i].t_ns, T_W_C});
    previous = current;
  }
  run.ms_per_frame = total_ms / static_cast<double>(sequence.frames.size() - 1);
  run.ate_m = eval::ate(sequence.ground_truth, trajectory).rmse_m;
  writeTrajectory(name, trajectory);
  return run;
}

}  // namespace vifusion::bench
