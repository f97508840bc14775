#include <cstdio>
#include <utility>
#include <vector>

#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/datasets/fault_injection.hpp"

namespace vifusion::datasets {
namespace {

class IncreasingTimes final : public DatasetReader {
 public:
  explicit IncreasingTimes(std::unique_ptr<DatasetReader> recording) : recording_(std::move(recording)) {
    const std::span<const std::string> skipped = recording_->skippedImuRows();
    skipped_imu_.assign(skipped.begin(), skipped.end());
    const std::span<const ImuSample> samples = recording_->imu();
    imu_.reserve(samples.size());
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const ImuSample& sample = samples[i];
      char reason[192] = "";
      if (!sample.gyro_rad_s.allFinite() || !sample.accel_mps2.allFinite()) {
        std::snprintf(reason, sizeof reason, "IMU sample %zu at t=%.6f s: a reading is not finite", i,
                      nsToSeconds(sample.t_ns));
      } else if (!imu_.empty() && sample.t_ns <= imu_.back().t_ns) {
        std::snprintf(reason, sizeof reason,
                      "IMU sample %zu at t=%.6f s: time does not increase (the sample before it was at t=%.6f s)", i,
                      nsToSeconds(sample.t_ns), nsToSeconds(imu_.back().t_ns));
      } else {
        imu_.push_back(sample);
        continue;
      }
      skipped_imu_.emplace_back(reason);
    }
  }

  const RigCalibration& calibration() const override { return recording_->calibration(); }
  std::size_t frameCount() const override { return recording_->frameCount(); }
  bool live() const override { return recording_->live(); }

  bool nextFrame(RgbdFrame& frame) override {
    if (!recording_->nextFrame(frame)) return false;
    if (have_last_ && frame.t_ns <= last_t_ns_) {
      char message[192];
      std::snprintf(message, sizeof message,
                    "frame %lld at t=%.6f s: time does not increase (the frame before it was at t=%.6f s)",
                    static_cast<long long>(frame.index), nsToSeconds(frame.t_ns), nsToSeconds(last_t_ns_));
      throw Error(message);
    }
    last_t_ns_ = frame.t_ns;
    have_last_ = true;
    return true;
  }

  std::optional<std::int64_t> listedFrameTimeNs(std::size_t index) const override {
    return recording_->listedFrameTimeNs(index);
  }
  std::span<const ImuSample> imu() const override { return imu_; }
  std::span<const std::string> skippedImuRows() const override { return skipped_imu_; }
  std::span<const StampedPose> groundTruth() const override { return recording_->groundTruth(); }
  std::span<const GroundTruthState> groundTruthStates() const override { return recording_->groundTruthStates(); }
  std::string describe() const override { return recording_->describe(); }

 private:
  std::unique_ptr<DatasetReader> recording_;
  std::vector<ImuSample> imu_;  ///< the recording's samples, those out of order or not finite left out
  std::vector<std::string> skipped_imu_;
  std::int64_t last_t_ns_ = 0;
  bool have_last_ = false;
};

}  // namespace

std::unique_ptr<DatasetReader> withIncreasingTimes(std::unique_ptr<DatasetReader> recording) {
  if (recording->live()) throw Error(recording->describe() + ": the live camera's driver orders its own streams");
  return std::make_unique<IncreasingTimes>(std::move(recording));
}

}  // namespace vifusion::datasets
