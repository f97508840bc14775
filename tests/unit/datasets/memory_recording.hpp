#pragma once
// A recording held in memory for the reader-wrapper tests (fault injection, looped replay): `frames` 4×3 frames at
// 30 Hz from t = 5 s, their depth (1000 + index) telling them apart, and a 200 Hz IMU over the same span whose gyro x
// is the sample's index.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "vifusion/core/time.hpp"
#include "vifusion/datasets/dataset_reader.hpp"

namespace vifusion::datasets::test {

inline constexpr std::int64_t kFramePeriodNs = kNsPerSecond / 30;
inline constexpr std::int64_t kImuPeriodNs = kNsPerSecond / 200;
inline constexpr std::int64_t kStartNs = 5 * kNsPerSecond;

class MemoryRecording final : public DatasetReader {
 public:
  explicit MemoryRecording(std::size_t frames, bool lists_times = true, bool rewindable = false)
      : frames_(frames), lists_times_(lists_times), rewindable_(rewindable) {
    calibration_.camera.width = 4;
    calibration_.camera.height = 3;
    const std::int64_t end_ns = kStartNs + static_cast<std::int64_t>(frames) * kFramePeriodNs;
    for (std::int64_t t = kStartNs - kFramePeriodNs; t <= end_ns; t += kImuPeriodNs) {
      ImuSample sample;
      sample.t_ns = t;
      sample.gyro_rad_s.x() = static_cast<double>(imu_.size());
      imu_.push_back(sample);
    }
  }
  const RigCalibration& calibration() const override { return calibration_; }
  std::size_t frameCount() const override { return frames_; }
  bool nextFrame(RgbdFrame& frame) override {
    if (next_ >= frames_) return false;
    frame.index = static_cast<std::int64_t>(next_);
    frame.t_ns = timeOf(next_);
    frame.depth.resize(4, 3, static_cast<std::uint16_t>(1000 + next_));
    frame.rgb.resize(4, 3, kColour);
    ++next_;
    return true;
  }
  bool rewind() override {
    if (!rewindable_) return false;
    next_ = 0;
    return true;
  }
  std::optional<std::int64_t> listedFrameTimeNs(std::size_t index) const override {
    if (!lists_times_ || index >= frames_) return std::nullopt;
    return timeOf(index);
  }
  std::span<const ImuSample> imu() const override { return imu_; }
  std::string describe() const override { return "memory recording"; }

  static std::int64_t timeOf(std::size_t index) { return kStartNs + static_cast<std::int64_t>(index) * kFramePeriodNs; }
  /// Every frame's colour: not black, so that a blanked frame shows.
  static constexpr Rgb8 kColour{10, 20, 30};

 private:
  std::size_t frames_;
  bool lists_times_;
  bool rewindable_;
  std::size_t next_ = 0;
  RigCalibration calibration_;
  std::vector<ImuSample> imu_;
};

}  // namespace vifusion::datasets::test
