#include "vifusion/datasets/tum_reader.hpp"

#include <algorithm>
#include <cctype>
#include <sstream>

#include "text_fields.hpp"
#include "tum_layout.hpp"
#include "vifusion/core/error.hpp"

namespace vifusion::datasets {
namespace {

std::vector<ImuSample> readAccelerometer(const std::filesystem::path& path) {
  static constexpr std::string_view kNames[] = {"timestamp", "ax", "ay", "az"};
  const std::string file = path.filename().string();
  const std::string text = detail::readTextFile(path, file);
  std::vector<ImuSample> samples;
  detail::forEachLine(text, [&](std::size_t line_number, std::string_view line) {
    if (detail::isCommentOrBlank(line)) return;
    const std::string prefix = detail::where(file, line_number);
    const std::vector<std::string_view> fields = detail::splitWhitespace(line);
    if (fields.size() != 4) {
      throw Error(prefix + "expected 4 columns 'timestamp ax ay az', found " + std::to_string(fields.size()));
    }
    ImuSample sample;  // gyro stays zero: the Kinect has no gyroscope
    sample.t_ns = detail::parseSecondsToNs(fields[0], prefix, kNames[0]);
    for (int axis = 0; axis < 3; ++axis) {
      sample.accel_mps2[axis] = detail::parseFinite(fields[1 + axis], prefix, kNames[1 + axis]);
    }
    if (!samples.empty()) detail::requireIncreasing(samples.back().t_ns, sample.t_ns, prefix);
    samples.push_back(sample);
  });
  return samples;
}

}  // namespace

PinholeCamera TumReader::intrinsicsForFolder(const std::string& folder_name) {
  std::string name = folder_name;
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::tolower(c); });
  const auto names = [&](const char* long_name, const char* short_name) {
    return name.find(long_name) != std::string::npos || name.find(short_name) != std::string::npos;
  };
  // https://cvg.cit.tum.de/data/datasets/rgbd-dataset/file_formats (calibrated colour cameras).
  if (names("freiburg1", "fr1")) return PinholeCamera::create(640, 480, 517.3, 516.5, 318.6, 255.3);
  if (names("freiburg2", "fr2")) return PinholeCamera::create(640, 480, 520.9, 521.0, 325.1, 249.7);
  if (names("freiburg3", "fr3")) return PinholeCamera::create(640, 480, 535.4, 539.2, 320.1, 247.6);
  return PinholeCamera::create(640, 480, 525.0, 525.0, 319.5, 239.5);
}

TumReader::TumReader(const std::filesystem::path& dir) : dir_(dir), decoder_(std::make_unique<detail::ImageDecoder>()) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir_, ec)) throw Error("tum: '" + dir_.string() + "' is not a directory");
  // absolute + normal form so that "tum:." and "tum:seq/" still name the sequence folder.
  const std::filesystem::path folder = std::filesystem::absolute(dir_, ec).lexically_normal();
  calibration_.camera =
      intrinsicsForFolder((folder.has_filename() ? folder : folder.parent_path()).filename().string());
  calibration_.depth_scale_m = 1.0 / 5000.0;
  frames_ = detail::readTumFrames(dir_);
  if (std::filesystem::exists(dir_ / "accelerometer.txt", ec))
    accelerometer_ = readAccelerometer(dir_ / "accelerometer.txt");
  if (std::filesystem::exists(dir_ / "groundtruth.txt", ec)) {
    ground_truth_ = detail::readTumTrajectory(dir_ / "groundtruth.txt", "groundtruth.txt");
  }
}

TumReader::~TumReader() = default;

std::optional<std::int64_t> TumReader::listedFrameTimeNs(std::size_t index) const {
  return index < frames_.size() ? std::optional<std::int64_t>(frames_[index].t_ns) : std::nullopt;
}

std::size_t TumReader::frameCount() const { return frames_.size(); }

bool TumReader::nextFrame(RgbdFrame& frame) {
  if (next_ >= frames_.size()) return false;
  const std::size_t index = next_++;  // past it even when it cannot be read: the caller may skip it
  detail::loadFrame(*decoder_, dir_, frames_[index], static_cast<std::int64_t>(index), calibration_, frame);
  return true;
}

std::string TumReader::describe() const {
  const PinholeCamera& c = calibration_.camera;
  std::ostringstream out;
  out << "TUM RGB-D '" << dir_.string() << "': " << frames_.size() << " frames, intrinsics " << c.fx << "/" << c.fy
      << "/" << c.cx << "/" << c.cy << " (TUM default for the folder name), " << accelerometer_.size()
      << " accelerometer-only IMU samples (zero gyro), " << ground_truth_.size() << " ground-truth poses";
  return out.str();
}

}  // namespace vifusion::datasets
