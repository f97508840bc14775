#include "vifusion/datasets/recalibrated_reader.hpp"

#include <sstream>
#include <utility>

#include "vifusion/core/error.hpp"
#include "vifusion/datasets/kalibr.hpp"

namespace vifusion::datasets {
namespace {

class RecalibratedReader final : public DatasetReader {
 public:
  RecalibratedReader(std::unique_ptr<DatasetReader> recording, const RigCalibration& calibration,
                     std::string calibration_name)
      : recording_(std::move(recording)), calibration_(calibration), calibration_name_(std::move(calibration_name)) {}

  const RigCalibration& calibration() const override { return calibration_; }
  std::size_t frameCount() const override { return recording_->frameCount(); }
  bool live() const override { return recording_->live(); }
  bool nextFrame(RgbdFrame& frame) override { return recording_->nextFrame(frame); }
  bool rewind() override { return recording_->rewind(); }
  std::span<const ImuSample> imu() const override { return recording_->imu(); }
  std::optional<std::int64_t> listedFrameTimeNs(std::size_t index) const override {
    return recording_->listedFrameTimeNs(index);
  }
  std::span<const std::string> skippedImuRows() const override { return recording_->skippedImuRows(); }
  std::span<const StampedPose> groundTruth() const override { return recording_->groundTruth(); }
  std::span<const GroundTruthState> groundTruthStates() const override { return recording_->groundTruthStates(); }
  std::string describe() const override {
    return recording_->describe() + "; calibration from " + calibration_name_ + " in place of its own";
  }

 private:
  std::unique_ptr<DatasetReader> recording_;
  RigCalibration calibration_;
  std::string calibration_name_;
};

}  // namespace

std::unique_ptr<DatasetReader> withCalibration(std::unique_ptr<DatasetReader> recording,
                                               const RigCalibration& calibration, const std::string& calibration_name) {
  const RigCalibration& own = recording->calibration();
  if (calibration.camera.width != own.camera.width || calibration.camera.height != own.camera.height) {
    std::ostringstream message;
    message << calibration_name << ": its camera is " << calibration.camera.width << "×" << calibration.camera.height
            << " px but the recording's images are " << own.camera.width << "×" << own.camera.height
            << " px; calibrate the rig at the size it records";
    throw Error(message.str());
  }
  if (calibration.depth_scale_m != own.depth_scale_m) {
    std::ostringstream message;
    message.precision(9);
    message << calibration_name << ": depth_scale_m " << calibration.depth_scale_m
            << " m per unit differs from the recording's " << own.depth_scale_m
            << "; the depth images would be read in the wrong units";
    throw Error(message.str());
  }
  return std::make_unique<RecalibratedReader>(std::move(recording), calibration, calibration_name);
}

std::unique_ptr<DatasetReader> withCalibrationFile(std::unique_ptr<DatasetReader> recording,
                                                   const std::string& calibration_yaml) {
  return withCalibration(std::move(recording), readCalibrationYaml(calibration_yaml), calibration_yaml);
}

}  // namespace vifusion::datasets
