#include "tum_layout.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "text_fields.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion::datasets::detail {
namespace {

// associate.py's default --max_difference.
constexpr std::int64_t kMaxAssociationDtNs = 20 * kNsPerMillisecond;

// 4-decimal quaternions (TUM ground truth) are off unit norm by ~1e-4; more is a corrupt line or a
// different column order, which normalising would silently hide.
constexpr double kMaxQuaternionNormError = 1e-3;

}  // namespace

std::vector<StampedFile> readStampedFileList(const std::filesystem::path& dir, const std::string& index_name) {
  const std::string text = readTextFile(dir / index_name, index_name);
  std::vector<StampedFile> files;
  forEachLine(text, [&](std::size_t line_number, std::string_view line) {
    if (isCommentOrBlank(line)) return;
    const std::string prefix = where(index_name, line_number);
    const std::vector<std::string_view> fields = splitWhitespace(line);
    if (fields.size() != 2) {
      throw Error(prefix + "expected 2 columns 'timestamp filename', found " + std::to_string(fields.size()));
    }
    StampedFile file{parseSecondsToNs(fields[0], prefix, "timestamp"), std::string(fields[1])};
    if (!files.empty()) requireIncreasing(files.back().t_ns, file.t_ns, prefix);
    requireFile(dir, file.path, prefix);
    files.push_back(std::move(file));
  });
  return files;
}

std::vector<FrameFiles> associate(const std::vector<StampedFile>& rgb, const std::vector<StampedFile>& depth,
                                  std::int64_t max_dt_ns) {
  struct Candidate {
    std::int64_t dt_ns;
    std::size_t rgb;
    std::size_t depth;
  };
  std::vector<Candidate> candidates;
  // Both lists are strictly increasing, so the depth window of each rgb stamp only moves forward.
  std::size_t first = 0;
  for (std::size_t i = 0; i < rgb.size(); ++i) {
    while (first < depth.size() && depth[first].t_ns <= rgb[i].t_ns - max_dt_ns) ++first;
    for (std::size_t j = first; j < depth.size() && depth[j].t_ns < rgb[i].t_ns + max_dt_ns; ++j) {
      candidates.push_back({std::llabs(depth[j].t_ns - rgb[i].t_ns), i, j});
    }
  }
  // Ties broken by position so the result does not depend on the sort implementation.
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    return a.dt_ns != b.dt_ns ? a.dt_ns < b.dt_ns : (a.rgb != b.rgb ? a.rgb < b.rgb : a.depth < b.depth);
  });
  std::vector<bool> rgb_used(rgb.size(), false);
  std::vector<bool> depth_used(depth.size(), false);
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (const Candidate& c : candidates) {
    if (rgb_used[c.rgb] || depth_used[c.depth]) continue;
    rgb_used[c.rgb] = depth_used[c.depth] = true;
    pairs.emplace_back(c.rgb, c.depth);
  }
  std::sort(pairs.begin(), pairs.end());
  std::vector<FrameFiles> frames;
  frames.reserve(pairs.size());
  for (const auto& [i, j] : pairs) frames.push_back({rgb[i].t_ns, depth[j].path, rgb[i].path});
  return frames;
}

std::vector<FrameFiles> readTumFrames(const std::filesystem::path& dir) {
  const std::vector<StampedFile> rgb = readStampedFileList(dir, "rgb.txt");
  const std::vector<StampedFile> depth = readStampedFileList(dir, "depth.txt");
  std::vector<FrameFiles> frames = associate(rgb, depth, kMaxAssociationDtNs);
  if (frames.empty()) {
    throw Error(dir.string() + ": no rgb.txt entry has a depth.txt entry within " + formatMs(kMaxAssociationDtNs) +
                " (" + std::to_string(rgb.size()) + " rgb, " + std::to_string(depth.size()) + " depth)");
  }
  return frames;
}

std::vector<StampedPose> readTumTrajectory(const std::filesystem::path& path, const std::string& display_name) {
  static constexpr std::string_view kNames[] = {"timestamp", "tx", "ty", "tz", "qx", "qy", "qz", "qw"};
  const std::string text = readTextFile(path, display_name);
  std::vector<StampedPose> poses;
  forEachLine(text, [&](std::size_t line_number, std::string_view line) {
    if (isCommentOrBlank(line)) return;
    const std::string prefix = where(display_name, line_number);
    const std::vector<std::string_view> fields = splitWhitespace(line);
    if (fields.size() != 8) {
      throw Error(prefix + "expected 8 columns 't tx ty tz qx qy qz qw', found " + std::to_string(fields.size()));
    }
    StampedPose pose;
    pose.t_ns = parseSecondsToNs(fields[0], prefix, kNames[0]);
    double v[8] = {};
    for (std::size_t k = 1; k < 8; ++k) v[k] = parseFinite(fields[k], prefix, kNames[k]);
    const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    if (!(std::abs(q.norm() - 1.0) <= kMaxQuaternionNormError)) {
      std::ostringstream message;
      message << prefix << "quaternion norm " << q.norm() << " is more than " << kMaxQuaternionNormError << " from 1";
      throw Error(message.str());
    }
    pose.T_world_body = SE3d(q, Eigen::Vector3d(v[1], v[2], v[3]));
    if (!poses.empty()) requireIncreasing(poses.back().t_ns, pose.t_ns, prefix);
    poses.push_back(pose);
  });
  return poses;
}

void loadFrame(ImageDecoder& decoder, const std::filesystem::path& dir, const FrameFiles& files, std::int64_t index,
               const RigCalibration& calibration, RgbdFrame& frame) {
  const int width = calibration.camera.width;
  const int height = calibration.camera.height;
  decoder.readDepthPng(dir, files.depth, width, height, frame.depth);
  decoder.readColor(dir, files.rgb, width, height, frame.rgb);
  frame.t_ns = files.t_ns;
  frame.index = index;
  frame.depth_scale_m = calibration.depth_scale_m;
}

}  // namespace vifusion::datasets::detail
