#pragma once
// A generated sequence written as a vifusion recording (`vifusion sim --out FILE.mcap`): the same topics as a
// live recording (recording/topics.hpp), the IMU interleaved with the frames in time order, the true camera
// pose per frame on /ground_truth/camera_pose, log times equal to the stamps. The simulator's full
// ground-truth states (groundtruth_states.csv of a dataset directory) are not part of a recording.

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "sequence_writer.hpp"
#include "vifusion/recording/recording_file.hpp"

namespace vifusion::cli {

class RecordingSequenceWriter final : public SequenceWriter {
 public:
  /// `source` names what is recorded ("sim:living_room_0").
  RecordingSequenceWriter(std::filesystem::path path, std::string source);
  ~RecordingSequenceWriter() override;

  /// Creates the file (refusing to replace an existing one) and writes the fixed part.
  void writeCalibration(const RigCalibration& calibration) override;
  void writeImu(std::span<const ImuSample> samples) override;
  void writeGroundTruthStates(std::span<const GroundTruthState> states) override;
  void writeFrame(std::int64_t t_ns, ImageView<const Rgb8> rgb, ImageView<const std::uint16_t> depth,
                  const SE3d& T_W_C) override;
  /// Writes the IMU samples after the last frame and completes the file.
  void finish() override;

 private:
  /// Writes the held IMU samples up to and including `t_ns`.
  void writeImuThrough(std::int64_t t_ns);
  void check(bool ok) const;

  std::filesystem::path path_;
  std::string source_;
  recording::RecordingFile file_;
  RigCalibration calibration_;
  std::vector<ImuSample> imu_;
  std::size_t next_imu_ = 0;
  RgbdFrame frame_;
  std::int64_t frames_ = 0;
};

}  // namespace vifusion::cli
