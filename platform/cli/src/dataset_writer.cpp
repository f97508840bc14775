#include "dataset_writer.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "vifusion/core/error.hpp"
#include "vifusion/datasets/euroc_imu.hpp"
#include "vifusion/datasets/ground_truth_states.hpp"
#include "vifusion/datasets/kalibr.hpp"

namespace vifusion::cli {
namespace {

std::FILE* openTemporary(const std::filesystem::path& path, const char* header) {
  std::FILE* file = std::fopen((path.string() + ".tmp").c_str(), "w");
  if (file == nullptr) throw Error(path.string() + ".tmp: cannot be written");
  std::fputs(header, file);
  return file;
}

void closeAndRename(std::FILE*& file, const std::filesystem::path& path) {
  if (file == nullptr) return;
  const bool ok = std::fclose(file) == 0;
  file = nullptr;
  if (!ok) throw Error(path.string() + ": write failed");
  std::filesystem::rename(path.string() + ".tmp", path);
}

void writeImage(const std::filesystem::path& path, const cv::Mat& image) {
  const std::filesystem::path temporary = path.string() + ".tmp.png";
  if (!cv::imwrite(temporary.string(), image)) throw Error(path.string() + ": cannot be written");
  std::filesystem::rename(temporary, path);
}

}  // namespace

std::string tumStamp(int64_t t_ns) {
  char text[32];
  std::snprintf(text, sizeof(text), "%lld.%06lld", static_cast<long long>(t_ns / 1'000'000'000),
                static_cast<long long>((t_ns % 1'000'000'000) / 1000));
  return text;
}

DatasetWriter::DatasetWriter(const std::filesystem::path& directory) : directory_(directory) {
  if (std::filesystem::exists(directory / "rgb.txt")) {
    throw Error(directory.string() + ": already holds a dataset (rgb.txt exists); choose another --out");
  }
  std::filesystem::create_directories(directory / "rgb");
  std::filesystem::create_directories(directory / "depth");
  rgb_index_ = openTemporary(directory / "rgb.txt", "# colour images\n# timestamp filename\n");
  depth_index_ =
      openTemporary(directory / "depth.txt", "# depth images (16-bit, 5000 per metre)\n# timestamp filename\n");
  groundtruth_ =
      openTemporary(directory / "groundtruth.txt", "# ground truth T_world_camera\n# timestamp tx ty tz qx qy qz qw\n");
}

DatasetWriter::~DatasetWriter() {
  for (std::FILE* file : {rgb_index_, depth_index_, groundtruth_}) {
    if (file != nullptr) std::fclose(file);  // unfinished: the .tmp files stay, final names are never half-written
  }
}

void DatasetWriter::writeFrame(int64_t t_ns, ImageView<const Rgb8> rgb, ImageView<const uint16_t> depth,
                               const SE3d& T_W_C) {
  const std::string stamp = tumStamp(t_ns);
  // OpenCV writes BGR; our images are RGB bytes.
  cv::Mat rgb_mat(rgb.height, rgb.width, CV_8UC3, const_cast<Rgb8*>(rgb.data), rgb.stride * sizeof(Rgb8));
  cv::Mat bgr;
  cv::cvtColor(rgb_mat, bgr, cv::COLOR_RGB2BGR);
  writeImage(directory_ / "rgb" / (stamp + ".png"), bgr);
  const cv::Mat depth_mat(depth.height, depth.width, CV_16UC1, const_cast<uint16_t*>(depth.data),
                          depth.stride * sizeof(uint16_t));
  writeImage(directory_ / "depth" / (stamp + ".png"), depth_mat);
  std::fprintf(rgb_index_, "%s rgb/%s.png\n", stamp.c_str(), stamp.c_str());
  std::fprintf(depth_index_, "%s depth/%s.png\n", stamp.c_str(), stamp.c_str());
  const Eigen::Vector3d& t = T_W_C.translation();
  const Eigen::Quaterniond& q = T_W_C.quaternion();
  std::fprintf(groundtruth_, "%s %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", stamp.c_str(), t.x(), t.y(), t.z(), q.x(),
               q.y(), q.z(), q.w());
}

void DatasetWriter::writeCalibration(const RigCalibration& calibration) {
  datasets::writeCalibrationYaml(directory_ / "calibration.yaml", calibration);
}

void DatasetWriter::writeImu(std::span<const ImuSample> samples) {
  const std::filesystem::path path = directory_ / "imu.csv";
  datasets::writeEurocImu(path.string() + ".tmp", samples);
  std::filesystem::rename(path.string() + ".tmp", path);
}

void DatasetWriter::writeGroundTruthStates(std::span<const GroundTruthState> states) {
  const std::filesystem::path path = directory_ / "groundtruth_states.csv";
  datasets::writeGroundTruthStates(path.string() + ".tmp", states);
  std::filesystem::rename(path.string() + ".tmp", path);
}

void DatasetWriter::finish() {
  closeAndRename(rgb_index_, directory_ / "rgb.txt");
  closeAndRename(depth_index_, directory_ / "depth.txt");
  closeAndRename(groundtruth_, directory_ / "groundtruth.txt");
}

}  // namespace vifusion::cli
