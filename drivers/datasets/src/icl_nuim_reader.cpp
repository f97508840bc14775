#include "vifusion/datasets/icl_nuim_reader.hpp"

#include <sstream>

#include "text_fields.hpp"
#include "tum_layout.hpp"
#include "vifusion/core/error.hpp"

namespace vifusion::datasets {
namespace {

// The stamps are frame numbers of a 30 Hz render; integer arithmetic keeps index/30 s exact to the ns.
std::int64_t frameStampToNs(std::int64_t stamp_as_seconds_ns) { return (stamp_as_seconds_ns + 15) / 30; }

std::vector<detail::FrameFiles> readAssociations(const std::filesystem::path& dir) {
  const std::string file = "associations.txt";
  const std::string text = detail::readTextFile(dir / file, file);
  std::vector<detail::FrameFiles> frames;
  detail::forEachLine(text, [&](std::size_t line_number, std::string_view line) {
    if (detail::isCommentOrBlank(line)) return;
    const std::string prefix = detail::where(file, line_number);
    const std::vector<std::string_view> fields = detail::splitWhitespace(line);
    if (fields.size() != 4) {
      throw Error(prefix + "expected 4 columns 't_depth depth_file t_rgb rgb_file', found " +
                  std::to_string(fields.size()));
    }
    detail::FrameFiles frame;
    frame.t_ns = frameStampToNs(detail::parseSecondsToNs(fields[0], prefix, "t_depth"));
    detail::parseSecondsToNs(fields[2], prefix, "t_rgb");  // validated; the depth stamp keys the frame
    frame.depth = std::string(fields[1]);
    frame.rgb = std::string(fields[3]);
    if (!frames.empty()) detail::requireIncreasing(frames.back().t_ns, frame.t_ns, prefix);
    detail::requireFile(dir, frame.depth, prefix);
    detail::requireFile(dir, frame.rgb, prefix);
    frames.push_back(std::move(frame));
  });
  if (frames.empty()) throw Error(file + ": no frames listed");
  return frames;
}

}  // namespace

IclNuimReader::IclNuimReader(const std::filesystem::path& dir)
    : dir_(dir), decoder_(std::make_unique<detail::ImageDecoder>()) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir_, ec)) throw Error("icl: '" + dir_.string() + "' is not a directory");
  calibration_.camera = PinholeCamera::create(640, 480, 481.20, -480.00, 319.5, 239.5);
  calibration_.depth_scale_m = 1.0 / 5000.0;
  frames_ = readAssociations(dir_);

  std::vector<std::filesystem::path> candidates;
  for (const auto& entry : std::filesystem::directory_iterator(dir_, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.size() > 12 && name.ends_with(".gt.freiburg")) candidates.push_back(entry.path());
  }
  if (ec) throw Error(dir_.string() + ": cannot list the folder: " + ec.message());
  if (candidates.size() > 1) {
    // Silently picking one would evaluate against the wrong trajectory.
    throw Error(dir_.string() + ": " + std::to_string(candidates.size()) +
                " *.gt.freiburg files; keep only the one belonging to this sequence");
  }
  if (!candidates.empty()) {
    ground_truth_file_ = candidates.front().filename().string();
    ground_truth_ = detail::readTumTrajectory(candidates.front(), ground_truth_file_);
    for (StampedPose& pose : ground_truth_) pose.t_ns = frameStampToNs(pose.t_ns);
  }
}

IclNuimReader::~IclNuimReader() = default;

std::optional<std::int64_t> IclNuimReader::listedFrameTimeNs(std::size_t index) const {
  return index < frames_.size() ? std::optional<std::int64_t>(frames_[index].t_ns) : std::nullopt;
}

std::size_t IclNuimReader::frameCount() const { return frames_.size(); }

bool IclNuimReader::nextFrame(RgbdFrame& frame) {
  if (next_ >= frames_.size()) return false;
  const std::size_t index = next_++;  // past it even when it cannot be read: the caller may skip it
  detail::loadFrame(*decoder_, dir_, frames_[index], static_cast<std::int64_t>(index), calibration_, frame);
  return true;
}

std::string IclNuimReader::describe() const {
  std::ostringstream out;
  out << "ICL-NUIM '" << dir_.string() << "': " << frames_.size()
      << " frames, intrinsics 481.2/-480/319.5/239.5, stamps = frame index / 30 s, ";
  if (ground_truth_.empty()) {
    out << "no ground truth";
  } else {
    out << ground_truth_.size() << " ground-truth poses from " << ground_truth_file_;
  }
  return out.str();
}

}  // namespace vifusion::datasets
