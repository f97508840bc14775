#include "vifusion/datasets/seven_scenes_reader.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cstdio>
#include <sstream>

#include "image_files.hpp"
#include "text_fields.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion::datasets {
namespace {

// 7-Scenes has no stamps; the Kinect ran at 30 Hz, so frame N is taken at N / 30 s.
std::int64_t frameTimeNs(int number) { return number * kNsPerSecond / 30; }

// KinectFusion accumulates its poses in float: the rotation blocks in 7-Scenes are off orthonormal by
// up to ~2e-4 (1.6e-4 in data/7scenes-50). 1e-3 accepts that and rejects a matrix that is no rotation.
constexpr double kRotationTolerance = 1e-3;

std::string frameName(int number, const char* suffix) {
  char name[48];
  std::snprintf(name, sizeof(name), "frame-%06d.%s", number, suffix);
  return name;
}

// "frame-000150.color.png" → 150; -1 for any other name (exactly six digits, as 7-Scenes writes).
int colorFrameNumber(const std::string& name) {
  static constexpr std::string_view kPrefix = "frame-";
  static constexpr std::string_view kSuffix = ".color.png";
  if (name.size() != kPrefix.size() + 6 + kSuffix.size() || !name.starts_with(kPrefix) || !name.ends_with(kSuffix)) {
    return -1;
  }
  int number = 0;
  for (std::size_t k = kPrefix.size(); k < kPrefix.size() + 6; ++k) {
    if (name[k] < '0' || name[k] > '9') return -1;
    number = number * 10 + (name[k] - '0');
  }
  return number;
}

/// Whitespace-separated numbers of a small matrix file, `rows` lines of `cols`.
Eigen::MatrixXd readMatrix(const std::filesystem::path& path, int rows, int cols) {
  const std::string file = path.filename().string();
  const std::string text = detail::readTextFile(path, file);
  Eigen::MatrixXd m(rows, cols);
  int row = 0;
  detail::forEachLine(text, [&](std::size_t line_number, std::string_view line) {
    if (detail::isCommentOrBlank(line)) return;
    const std::string prefix = detail::where(file, line_number);
    if (row == rows) throw Error(prefix + "more than " + std::to_string(rows) + " rows");
    const std::vector<std::string_view> fields = detail::splitWhitespace(line);
    if (fields.size() != static_cast<std::size_t>(cols)) {
      throw Error(prefix + "expected " + std::to_string(cols) + " columns, found " + std::to_string(fields.size()));
    }
    for (int c = 0; c < cols; ++c) {
      char name[32];  // element name "m<row><col>", 1-based as a person counts
      std::snprintf(name, sizeof(name), "m%d%d", row + 1, c + 1);
      m(row, c) = detail::parseFinite(fields[static_cast<std::size_t>(c)], prefix, name);
    }
    ++row;
  });
  if (row != rows) throw Error(file + ": expected " + std::to_string(rows) + " rows, found " + std::to_string(row));
  return m;
}

SE3d readPose(const std::filesystem::path& path) {
  const Eigen::Matrix4d m = readMatrix(path, 4, 4);
  const Eigen::Matrix3d R = m.topLeftCorner<3, 3>();
  const std::string file = path.filename().string();
  if ((m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9) {
    throw Error(file + ": bottom row must be 0 0 0 1");
  }
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > kRotationTolerance ||
      R.determinant() <= 0.0) {
    throw Error(file + ": rotation block is not a rotation matrix");
  }
  // The nearest rotation (Frobenius norm) to the slightly non-orthonormal block: R = U·Vᵀ.
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Matrix3d R_nearest = svd.matrixU() * svd.matrixV().transpose();
  return SE3d(Eigen::Quaterniond(R_nearest), m.topRightCorner<3, 1>());
}

PinholeCamera readIntrinsics(const std::filesystem::path& path) {
  const Eigen::Matrix3d K = readMatrix(path, 3, 3);
  const std::string file = path.filename().string();
  if (K(0, 1) != 0.0 || K(1, 0) != 0.0 || K(2, 0) != 0.0 || K(2, 1) != 0.0 || K(2, 2) != 1.0) {
    throw Error(file + ": expected K = [fx 0 cx; 0 fy cy; 0 0 1]");
  }
  try {
    return PinholeCamera::create(640, 480, K(0, 0), K(1, 1), K(0, 2), K(1, 2));
  } catch (const std::invalid_argument& e) {
    throw Error(file + ": " + e.what());
  }
}

}  // namespace

SevenScenesReader::SevenScenesReader(const std::filesystem::path& dir)
    : dir_(dir), frames_dir_(dir), decoder_(std::make_unique<detail::ImageDecoder>()) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir_, ec)) throw Error("7scenes: '" + dir_.string() + "' is not a directory");
  const auto listFrames = [&](const std::filesystem::path& folder) {
    std::vector<int> numbers;
    std::error_code list_error;
    for (const auto& entry : std::filesystem::directory_iterator(folder, list_error)) {
      const int number = colorFrameNumber(entry.path().filename().string());
      if (number >= 0) numbers.push_back(number);
    }
    if (list_error) throw Error("7scenes: cannot list '" + folder.string() + "': " + list_error.message());
    std::sort(numbers.begin(), numbers.end());
    return numbers;
  };
  frame_numbers_ = listFrames(dir_);
  if (frame_numbers_.empty() && std::filesystem::is_directory(dir_ / "rgbd-frames", ec)) {
    frames_dir_ = dir_ / "rgbd-frames";
    frame_numbers_ = listFrames(frames_dir_);
  }
  if (frame_numbers_.empty()) throw Error("7scenes: no frame-XXXXXX.color.png in '" + dir_.string() + "'");

  calibration_.camera = PinholeCamera::create(640, 480, 585.0, 585.0, 320.0, 240.0);
  calibration_.depth_scale_m = 0.001;
  for (const auto& folder : {dir_, frames_dir_}) {
    if (std::filesystem::exists(folder / "camera-intrinsics.txt", ec)) {
      calibration_.camera = readIntrinsics(folder / "camera-intrinsics.txt");
      intrinsics_from_file_ = true;
      break;
    }
  }

  // Poses are all-or-nothing: a sequence with some missing would give an evaluation with holes.
  const bool has_poses = std::filesystem::exists(frames_dir_ / frameName(frame_numbers_.front(), "pose.txt"), ec);
  for (const int number : frame_numbers_) {
    detail::requireFile(frames_dir_, frameName(number, "depth.png"), frameName(number, "color.png") + ": ");
    if (!has_poses) continue;
    const std::string pose_file = frameName(number, "pose.txt");
    detail::requireFile(frames_dir_, pose_file, frameName(number, "color.png") + ": ");
    ground_truth_.push_back({frameTimeNs(number), readPose(frames_dir_ / pose_file)});
  }
}

SevenScenesReader::~SevenScenesReader() = default;

std::optional<std::int64_t> SevenScenesReader::listedFrameTimeNs(std::size_t index) const {
  return index < frame_numbers_.size() ? std::optional<std::int64_t>(frameTimeNs(frame_numbers_[index])) : std::nullopt;
}

bool SevenScenesReader::nextFrame(RgbdFrame& frame) {
  if (next_ >= frame_numbers_.size()) return false;
  const std::size_t index = next_++;  // past it even when it cannot be read: the caller may skip it
  const int number = frame_numbers_[index];
  const int width = calibration_.camera.width;
  const int height = calibration_.camera.height;
  decoder_->readDepthPng(frames_dir_, frameName(number, "depth.png"), width, height, frame.depth);
  decoder_->readColor(frames_dir_, frameName(number, "color.png"), width, height, frame.rgb);
  // 7-Scenes marks missing depth with 65535; downstream only knows 0 as invalid.
  std::uint16_t* depth = frame.depth.data();
  std::replace(depth, depth + frame.depth.pixelCount(), std::uint16_t{65535}, std::uint16_t{0});
  frame.t_ns = frameTimeNs(number);
  frame.index = static_cast<std::int64_t>(index);
  frame.depth_scale_m = calibration_.depth_scale_m;
  return true;
}

std::string SevenScenesReader::describe() const {
  const PinholeCamera& c = calibration_.camera;
  std::ostringstream out;
  out << "7-Scenes '" << dir_.string() << "': " << frame_numbers_.size() << " frames (frame-" << frame_numbers_.front()
      << " … " << frame_numbers_.back() << "), stamps = frame number / 30 s, intrinsics " << c.fx << "/" << c.fy << "/"
      << c.cx << "/" << c.cy << (intrinsics_from_file_ ? " from camera-intrinsics.txt" : " (7-Scenes default)") << ", "
      << ground_truth_.size() << " KinectFusion poses";
  return out.str();
}

}  // namespace vifusion::datasets
