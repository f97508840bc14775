#pragma once
// TUM RGB-D benchmark sequences (Sturm et al., IROS 2012), e.g. rgbd_dataset_freiburg1_xyz/:
//   rgb.txt, depth.txt       "t filename" per line, '#' comments; t in seconds
//   rgb/, depth/             8-bit colour PNG, 16-bit depth PNG at 5000 units per metre (0 = invalid)
//   groundtruth.txt          optional, "t tx ty tz qx qy qz qw" = T_world_camera (motion capture)
//   accelerometer.txt        optional, "t ax ay az" [m/s²] from the Kinect's accelerometer
// Colour and depth are associated as associate.py does (nearest stamps within 0.02 s, each used once);
// a frame carries the rgb stamp, which is what TUM ground truth and evaluation key by.
//
// IMU: accelerometer.txt becomes ImuSamples with ZERO gyro_rad_s — the Kinect has no gyroscope — so
// these samples suit gravity-direction checks only, never rgbdi/gyro tracking. Their axes are the
// Kinect body's, not the optical frame's, and TUM publishes no extrinsic: T_S_C is left identity.
//
// Intrinsics: TUM's published values chosen by the folder name ("freiburg1"/"fr1", fr2, fr3), else the
// ROS default 525/525/319.5/239.5; 640×480. The published distortion is ignored (images as recorded).

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vifusion/datasets/dataset_reader.hpp"

namespace vifusion::datasets {

namespace detail {
struct FrameFiles;
class ImageDecoder;
}  // namespace detail

class TumReader final : public DatasetReader {
 public:
  /// Parses and checks every index file and the existence of every referenced image.
  /// @throws vifusion::Error naming the file and line of the first problem.
  explicit TumReader(const std::filesystem::path& dir);
  ~TumReader() override;

  /// TUM's intrinsics for the Kinect named in `folder_name` (fr1, fr2, fr3), else 525/525/319.5/239.5.
  static PinholeCamera intrinsicsForFolder(const std::string& folder_name);

  const RigCalibration& calibration() const override { return calibration_; }
  std::size_t frameCount() const override;
  std::optional<std::int64_t> listedFrameTimeNs(std::size_t index) const override;
  bool nextFrame(RgbdFrame& frame) override;
  bool rewind() override {
    next_ = 0;
    return true;
  }
  std::span<const ImuSample> imu() const override { return accelerometer_; }
  std::span<const StampedPose> groundTruth() const override { return ground_truth_; }
  std::string describe() const override;

 private:
  std::filesystem::path dir_;
  RigCalibration calibration_;
  std::vector<detail::FrameFiles> frames_;
  std::vector<ImuSample> accelerometer_;
  std::vector<StampedPose> ground_truth_;
  std::size_t next_ = 0;
  std::unique_ptr<detail::ImageDecoder> decoder_;
};

}  // namespace vifusion::datasets
