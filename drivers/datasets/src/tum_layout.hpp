#pragma once
// Private: the TUM RGB-D file layout shared by the TUM, ICL-NUIM and our own dataset readers —
// index files of "t path" lines, trajectory files "t tx ty tz qx qy qz qw", and loading one frame.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "image_files.hpp"
#include "vifusion/core/rig_calibration.hpp"
#include "vifusion/core/sensor_data.hpp"
#include "vifusion/datasets/dataset_reader.hpp"

namespace vifusion::datasets::detail {

/// One RGB-D frame's files, relative to the dataset folder, and its stamp.
struct FrameFiles {
  std::int64_t t_ns = 0;
  std::string depth;
  std::string rgb;
};

/// A "t path" index file (rgb.txt, depth.txt), stamps strictly increasing, every file present.
struct StampedFile {
  std::int64_t t_ns = 0;
  std::string path;
};
std::vector<StampedFile> readStampedFileList(const std::filesystem::path& dir, const std::string& index_name);

/// associate.py: every (rgb, depth) pair closer than max_dt_ns is a candidate; candidates are taken
/// in order of increasing |Δt|, each stamp at most once; the result is in rgb time order and stamped
/// with the rgb time (TUM's ground truth and evaluation key frames by their rgb stamp).
std::vector<FrameFiles> associate(const std::vector<StampedFile>& rgb, const std::vector<StampedFile>& depth,
                                  std::int64_t max_dt_ns);

/// rgb.txt + depth.txt of `dir`, associated within 0.02 s as associate.py's default.
/// @throws vifusion::Error if either is malformed or no pair associates.
std::vector<FrameFiles> readTumFrames(const std::filesystem::path& dir);

/// A TUM trajectory file (T_world_camera), stamps strictly increasing, quaternion norms within 1e-3
/// of 1 (rounding in 4-decimal files; more means a corrupt line). `display_name` names it in errors.
std::vector<StampedPose> readTumTrajectory(const std::filesystem::path& path, const std::string& display_name);

/// Decodes `files` into `frame` (sizes from calibration.camera, depth scale from calibration).
void loadFrame(ImageDecoder& decoder, const std::filesystem::path& dir, const FrameFiles& files, std::int64_t index,
               const RigCalibration& calibration, RgbdFrame& frame);

}  // namespace vifusion::datasets::detail
