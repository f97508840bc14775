#include "vifusion/test/seven_scenes_frame.hpp"

#include <cstdio>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "vifusion/core/error.hpp"
#include "vifusion/test/data_paths.hpp"

namespace vifusion::test {

SevenScenesFrame loadSevenScenesFrame(int index) {
  char name[64];
  std::snprintf(name, sizeof(name), "frame-%06d", index);
  const auto folder = dataDir() / "7scenes-50" / "rgbd-frames";
  const auto depth_path = folder / (std::string(name) + ".depth.png");
  const auto color_path = folder / (std::string(name) + ".color.png");
  const cv::Mat depth = cv::imread(depth_path.string(), cv::IMREAD_ANYDEPTH);
  const cv::Mat bgr = cv::imread(color_path.string(), cv::IMREAD_COLOR);
  if (depth.empty()) throw Error(depth_path.string() + ": missing or unreadable (set VIFUSION_DATA_DIR?)");
  if (depth.type() != CV_16UC1) throw Error(depth_path.string() + ": not a 16-bit single-channel PNG");
  if (bgr.empty()) throw Error(color_path.string() + ": missing or unreadable");
  if (bgr.size() != depth.size()) throw Error(color_path.string() + ": size differs from the depth image");

  const auto pose_path = folder / (std::string(name) + ".pose.txt");
  std::ifstream pose_file(pose_path);
  Eigen::Matrix4d T = Eigen::Matrix4d::Zero();
  for (int i = 0; i < 16; ++i) {
    if (!(pose_file >> T(i / 4, i % 4))) throw Error(pose_path.string() + ": expected 16 numbers");
  }

  SevenScenesFrame frame;
  // KinectFusion rotations are orthonormal to ~1e-7; the quaternion constructor normalises.
  frame.T_W_C = SE3d(Eigen::Quaterniond(Eigen::Matrix3d(T.topLeftCorner<3, 3>())), T.topRightCorner<3, 1>());
  frame.camera = PinholeCamera::create(depth.cols, depth.rows, 585.0, 585.0, 320.0, 240.0);
  frame.depth_mm.resize(depth.cols, depth.rows);
  frame.rgb.resize(depth.cols, depth.rows);
  for (int y = 0; y < depth.rows; ++y) {
    for (int x = 0; x < depth.cols; ++x) {
      frame.depth_mm(x, y) = depth.at<std::uint16_t>(y, x);
      const cv::Vec3b& pixel = bgr.at<cv::Vec3b>(y, x);
      frame.rgb(x, y) = {pixel[2], pixel[1], pixel[0]};
    }
  }
  return frame;
}

}  // namespace vifusion::test
