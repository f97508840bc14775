#pragma once
// Our own dataset directories (DESIGN §5), written by `vifusion sim` and meant for recordings too:
//   rgb.txt, depth.txt, rgb/, depth/   TUM layout; depth 16-bit PNG at calibration.yaml's depth_scale_m
//   calibration.yaml                   required; schema in kalibr.hpp (intrinsics, T_cam_imu, noise, g_W)
//   imu.csv                            required; EuRoC layout (euroc_imu.hpp), stamps on the frames' time base
//   groundtruth.txt                    optional; TUM format, T_world_camera
//   groundtruth_states.csv             optional; true IMU states (ground_truth_states.hpp)
// Images must have calibration.yaml's resolution.

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

class VifusionDatasetReader final : public DatasetReader {
 public:
  /// @throws vifusion::Error naming the file and line of the first problem.
  explicit VifusionDatasetReader(const std::filesystem::path& dir);
  ~VifusionDatasetReader() override;

  const RigCalibration& calibration() const override { return calibration_; }
  std::size_t frameCount() const override;
  std::optional<std::int64_t> listedFrameTimeNs(std::size_t index) const override;
  bool nextFrame(RgbdFrame& frame) override;
  bool rewind() override {
    next_ = 0;
    return true;
  }
  std::span<const ImuSample> imu() const override { return imu_; }
  std::span<const std::string> skippedImuRows() const override { return skipped_imu_rows_; }
  std::span<const StampedPose> groundTruth() const override { return ground_truth_; }
  std::span<const GroundTruthState> groundTruthStates() const override { return states_; }
  std::string describe() const override;

 private:
  std::filesystem::path dir_;
  RigCalibration calibration_;
  std::vector<detail::FrameFiles> frames_;
  std::vector<ImuSample> imu_;
  std::vector<std::string> skipped_imu_rows_;
  std::vector<StampedPose> ground_truth_;
  std::vector<GroundTruthState> states_;
  std::size_t next_ = 0;
  std::unique_ptr<detail::ImageDecoder> decoder_;
};

}  // namespace vifusion::datasets
