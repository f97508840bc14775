#pragma once
// ICL-NUIM living-room / office sequences (Handa et al., ICRA 2014), TUM-compatible release:
//   associations.txt   "t_depth depth/N.png t_rgb rgb/N.png" per line
//   rgb/, depth/       8-bit colour PNG, 16-bit depth PNG at 5000 units per metre
//   *.gt.freiburg      optional, TUM-format T_world_camera (the one file of that suffix in the folder)
// ICL-NUIM stamps are frame indices, not seconds; the frames were rendered as a 30 Hz camera, so
// every stamp s (associations and ground truth alike) becomes t = s / 30 s, matching
// data/icl-nuim-trajectories. A frame carries its depth stamp (column 1).
// Intrinsics 640×480, fx 481.20, fy −480.00 (the renderer flips rows; see pinhole_camera.hpp), cx 319.5,
// cy 239.5, exactly as published; no IMU.

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

class IclNuimReader final : public DatasetReader {
 public:
  /// @throws vifusion::Error naming the file and line of the first problem in the index or ground truth.
  explicit IclNuimReader(const std::filesystem::path& dir);
  ~IclNuimReader() override;

  const RigCalibration& calibration() const override { return calibration_; }
  std::size_t frameCount() const override;
  std::optional<std::int64_t> listedFrameTimeNs(std::size_t index) const override;
  bool nextFrame(RgbdFrame& frame) override;
  bool rewind() override {
    next_ = 0;
    return true;
  }
  std::span<const StampedPose> groundTruth() const override { return ground_truth_; }
  std::string describe() const override;

 private:
  std::filesystem::path dir_;
  RigCalibration calibration_;
  std::vector<detail::FrameFiles> frames_;
  std::vector<StampedPose> ground_truth_;
  std::string ground_truth_file_;
  std::size_t next_ = 0;
  std::unique_ptr<detail::ImageDecoder> decoder_;
};

}  // namespace vifusion::datasets
