#pragma once
// Writes a dataset directory in the layout of DESIGN.md §5, readable by every TUM RGB-D tool and
// by our `dataset:DIR` reader:
//   rgb/<t>.png, depth/<t>.png (16-bit, 5000 per metre), rgb.txt, depth.txt,
//   groundtruth.txt (T_world_camera, TUM), imu.csv (EuRoC layout), groundtruth_states.csv,
//   calibration.yaml.
// Files are written to "<name>.tmp" and renamed when complete, so an interrupted run never leaves
// a truncated file under its final name.

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <span>

#include "sequence_writer.hpp"
#include "vifusion/core/image.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/core/sensor_data.hpp"

namespace vifusion::cli {

class DatasetWriter final : public SequenceWriter {
 public:
  /// Creates `directory` (and rgb/, depth/); refuses a directory that already holds a dataset.
  explicit DatasetWriter(const std::filesystem::path& directory);
  ~DatasetWriter() override;
  DatasetWriter(const DatasetWriter&) = delete;
  DatasetWriter& operator=(const DatasetWriter&) = delete;

  /// Writes one frame's images and index lines; T_W_C is the true camera pose at t_ns.
  void writeFrame(int64_t t_ns, ImageView<const Rgb8> rgb, ImageView<const uint16_t> depth, const SE3d& T_W_C) override;
  /// calibration.yaml.
  void writeCalibration(const RigCalibration& calibration) override;
  void writeImu(std::span<const ImuSample> samples) override;
  void writeGroundTruthStates(std::span<const GroundTruthState> states) override;
  /// Closes the index files and moves them to their final names.
  void finish() override;

  const std::filesystem::path& directory() const { return directory_; }

 private:
  std::filesystem::path directory_;
  std::FILE* rgb_index_ = nullptr;
  std::FILE* depth_index_ = nullptr;
  std::FILE* groundtruth_ = nullptr;
};

/// TUM stamp text of t_ns: seconds with 6 decimals ("1305031102.175304").
std::string tumStamp(int64_t t_ns);

}  // namespace vifusion::cli
