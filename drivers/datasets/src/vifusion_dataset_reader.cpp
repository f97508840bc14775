#include "vifusion/datasets/vifusion_dataset_reader.hpp"

#include <sstream>

#include "tum_layout.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/datasets/euroc_imu.hpp"
#include "vifusion/datasets/ground_truth_states.hpp"
#include "vifusion/datasets/kalibr.hpp"

namespace vifusion::datasets {

VifusionDatasetReader::VifusionDatasetReader(const std::filesystem::path& dir)
    : dir_(dir), decoder_(std::make_unique<detail::ImageDecoder>()) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir_, ec)) throw Error("dataset: '" + dir_.string() + "' is not a directory");
  calibration_ = readCalibrationYaml(dir_ / "calibration.yaml");
  frames_ = detail::readTumFrames(dir_);
  imu_ = readEurocImu(dir_ / "imu.csv", &skipped_imu_rows_);
  if (std::filesystem::exists(dir_ / "groundtruth.txt", ec)) {
    ground_truth_ = detail::readTumTrajectory(dir_ / "groundtruth.txt", "groundtruth.txt");
  }
  if (std::filesystem::exists(dir_ / "groundtruth_states.csv", ec)) {
    states_ = readGroundTruthStates(dir_ / "groundtruth_states.csv");
  }
}

VifusionDatasetReader::~VifusionDatasetReader() = default;

std::optional<std::int64_t> VifusionDatasetReader::listedFrameTimeNs(std::size_t index) const {
  return index < frames_.size() ? std::optional<std::int64_t>(frames_[index].t_ns) : std::nullopt;
}

std::size_t VifusionDatasetReader::frameCount() const { return frames_.size(); }

bool VifusionDatasetReader::nextFrame(RgbdFrame& frame) {
  if (next_ >= frames_.size()) return false;
  const std::size_t index = next_++;  // past it even when it cannot be read: the caller may skip it
  detail::loadFrame(*decoder_, dir_, frames_[index], static_cast<std::int64_t>(index), calibration_, frame);
  return true;
}

std::string VifusionDatasetReader::describe() const {
  const PinholeCamera& c = calibration_.camera;
  std::ostringstream out;
  out << "vifusion dataset '" << dir_.string() << "': " << frames_.size() << " frames " << c.width << "x" << c.height
      << ", " << imu_.size() << " IMU samples, " << ground_truth_.size() << " ground-truth poses, " << states_.size()
      << " ground-truth states, calibration.yaml";
  return out.str();
}

}  // namespace vifusion::datasets
