#pragma once
// Microsoft 7-Scenes sequences (Shotton et al., CVPR 2013), e.g. seq-01/:
//   frame-XXXXXX.color.png   8-bit colour 640×480
//   frame-XXXXXX.depth.png   16-bit depth in millimetres; 0 and 65535 are invalid (65535 becomes 0)
//   frame-XXXXXX.pose.txt    4×4 camera-to-world matrix (T_world_camera), from KinectFusion
//   camera-intrinsics.txt    optional 3×3 K (as shipped with andyzeng/tsdf-fusion), else 585/585/320/240
// The frames may also sit in an rgbd-frames/ subfolder (tsdf-fusion's layout; data/7scenes-50).
// There are no stamps: frame-N is taken at N / 30 s (the Kinect's rate), so gaps in the numbering stay
// gaps in time. Colour and depth are not registered to each other in 7-Scenes; no IMU.

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vifusion/datasets/dataset_reader.hpp"

namespace vifusion::datasets {

namespace detail {
class ImageDecoder;
}  // namespace detail

class SevenScenesReader final : public DatasetReader {
 public:
  /// Lists the frames, checks each has its depth (and pose, if the first one has a pose), reads the
  /// poses and the intrinsics. @throws vifusion::Error naming the file of the first problem.
  explicit SevenScenesReader(const std::filesystem::path& dir);
  ~SevenScenesReader() override;

  const RigCalibration& calibration() const override { return calibration_; }
  std::size_t frameCount() const override { return frame_numbers_.size(); }
  std::optional<std::int64_t> listedFrameTimeNs(std::size_t index) const override;
  bool nextFrame(RgbdFrame& frame) override;
  bool rewind() override {
    next_ = 0;
    return true;
  }
  std::span<const StampedPose> groundTruth() const override { return ground_truth_; }
  std::string describe() const override;

 private:
  std::filesystem::path dir_;         ///< the folder given
  std::filesystem::path frames_dir_;  ///< where the frame-* files are (dir_ or dir_/rgbd-frames)
  RigCalibration calibration_;
  bool intrinsics_from_file_ = false;
  std::vector<int> frame_numbers_;  ///< the XXXXXX of each frame, increasing
  std::vector<StampedPose> ground_truth_;
  std::size_t next_ = 0;
  std::unique_ptr<detail::ImageDecoder> decoder_;
};

}  // namespace vifusion::datasets
