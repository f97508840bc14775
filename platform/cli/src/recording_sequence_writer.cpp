#include "recording_sequence_writer.hpp"

#include <algorithm>

#include "vifusion/core/error.hpp"

namespace vifusion::cli {

RecordingSequenceWriter::RecordingSequenceWriter(std::filesystem::path path, std::string source)
    : path_(std::move(path)), source_(std::move(source)) {
  if (std::filesystem::exists(path_)) throw Error(path_.string() + ": already exists; choose another --out");
}

RecordingSequenceWriter::~RecordingSequenceWriter() = default;

void RecordingSequenceWriter::check(bool ok) const {
  if (!ok) throw Error(path_.string() + ": " + file_.error());
}

void RecordingSequenceWriter::writeCalibration(const RigCalibration& calibration) {
  calibration_ = calibration;
  recording::RecordingHeader header;
  header.source = source_;
  header.calibration = calibration;
  header.imu_rate_hz = calibration.imu.rate_hz;
  check(file_.open(path_, header));
}

void RecordingSequenceWriter::writeImu(std::span<const ImuSample> samples) {
  imu_.assign(samples.begin(), samples.end());
  next_imu_ = 0;
}

void RecordingSequenceWriter::writeGroundTruthStates(std::span<const GroundTruthState> /*states*/) {}

void RecordingSequenceWriter::writeImuThrough(std::int64_t t_ns) {
  for (; next_imu_ < imu_.size() && imu_[next_imu_].t_ns <= t_ns; ++next_imu_) {
    check(file_.writeImu(imu_[next_imu_], imu_[next_imu_].t_ns));
  }
}

void RecordingSequenceWriter::writeFrame(std::int64_t t_ns, ImageView<const Rgb8> rgb,
                                         ImageView<const std::uint16_t> depth, const SE3d& T_W_C) {
  writeImuThrough(t_ns);
  frame_.depth.resize(depth.width, depth.height);
  frame_.rgb.resize(rgb.width, rgb.height);
  for (int y = 0; y < depth.height; ++y) std::copy_n(&depth(0, y), depth.width, &frame_.depth(0, y));
  for (int y = 0; y < rgb.height; ++y) std::copy_n(&rgb(0, y), rgb.width, &frame_.rgb(0, y));
  frame_.t_ns = t_ns;
  frame_.index = frames_++;
  frame_.depth_scale_m = calibration_.depth_scale_m;
  check(file_.writeFrame(frame_, t_ns));
  check(file_.writeGroundTruthPose(t_ns, T_W_C, t_ns));
}

void RecordingSequenceWriter::finish() {
  writeImuThrough(imu_.empty() ? 0 : imu_.back().t_ns);
  check(file_.close());
}

}  // namespace vifusion::cli
