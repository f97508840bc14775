#include "vifusion/eval/trajectory_io.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>

#include "vifusion/core/atomic_file.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion::eval {
namespace {

constexpr std::array<std::string_view, 8> kFieldNames = {"t", "tx", "ty", "tz", "qx", "qy", "qz", "qw"};

// A quaternion written with 4 decimals (TUM ground truth) is off unit norm by ~1e-4; anything much
// larger is a corrupt line or a different column order, which normalising would silently hide.
constexpr double kMaxQuaternionNormError = 1e-3;

// Separators as associate.py treats them (commas and tabs become spaces); '\r' so CRLF files parse.
bool isSeparator(char c) { return c == ' ' || c == ',' || c == '\t' || c == '\r'; }

std::vector<std::string_view> splitFields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t pos = 0;
  while (pos < line.size()) {
    while (pos < line.size() && isSeparator(line[pos])) ++pos;
    const std::size_t begin = pos;
    while (pos < line.size() && !isSeparator(line[pos])) ++pos;
    if (pos > begin) fields.push_back(line.substr(begin, pos - begin));
  }
  return fields;
}

// "5 ms", "1.5 ms", "250 us", "3 ns": the unit a person reading the error thinks in.
std::string formatDuration(std::int64_t dt_ns) {
  std::ostringstream out;
  const std::int64_t magnitude_ns = std::llabs(dt_ns);
  if (magnitude_ns >= kNsPerMillisecond) {
    out << static_cast<double>(dt_ns) / static_cast<double>(kNsPerMillisecond) << " ms";
  } else if (magnitude_ns >= kNsPerMicrosecond) {
    out << static_cast<double>(dt_ns) / static_cast<double>(kNsPerMicrosecond) << " us";
  } else {
    out << dt_ns << " ns";
  }
  return out.str();
}

StampedPose parseLine(const std::vector<std::string_view>& fields, const std::string& where) {
  if (fields.size() != kFieldNames.size()) {
    throw Error(where + "expected 8 numbers, found " + std::to_string(fields.size()));
  }
  std::array<double, 8> values{};
  for (std::size_t k = 0; k < fields.size(); ++k) {
    const std::string_view field = fields[k];
    const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), values[k]);
    if (ec != std::errc() || end != field.data() + field.size() || !std::isfinite(values[k])) {
      throw Error(where + "field '" + std::string(kFieldNames[k]) + "' is not a finite number: '" + std::string(field) +
                  "'");
    }
  }
  StampedPose pose;
  if (const auto exact = decimalSecondsToNs(fields[0])) {
    pose.t_ns = *exact;
  } else {
    // Exponent notation, a sign or sub-nanosecond digits: round through double instead.
    if (std::abs(values[0]) > nsToSeconds(kMaxFileStampNs)) {
      throw Error(where + "field 't' is beyond the " + std::to_string(kMaxFileStampNs / kNsPerSecond) +
                  " s a stamp may hold: '" + std::string(fields[0]) + "'");
    }
    pose.t_ns = std::clamp(secondsToNs(values[0]), -kMaxFileStampNs, kMaxFileStampNs);
  }
  const Eigen::Quaterniond q(values[7], values[4], values[5], values[6]);
  const double norm_error = std::abs(q.norm() - 1.0);
  if (!(norm_error <= kMaxQuaternionNormError)) {
    std::ostringstream message;
    message << where << "quaternion norm " << q.norm() << " is more than " << kMaxQuaternionNormError << " from 1";
    throw Error(message.str());
  }
  pose.T_world_body = SE3d(q, Eigen::Vector3d(values[1], values[2], values[3]));
  return pose;
}

// Stamp in seconds with exactly 9 decimals, so writeTum → readTum reproduces t_ns.
std::string formatStamp(std::int64_t t_ns) {
  std::ostringstream out;
  if (t_ns < 0) out << '-';
  const std::uint64_t magnitude_ns =
      t_ns < 0 ? 0ULL - static_cast<std::uint64_t>(t_ns) : static_cast<std::uint64_t>(t_ns);
  out << magnitude_ns / kNsPerSecond << '.' << std::setw(9) << std::setfill('0') << magnitude_ns % kNsPerSecond;
  return out.str();
}

}  // namespace

std::vector<StampedPose> parseTum(std::string_view text, std::string_view source_name) {
  std::vector<StampedPose> poses;
  std::size_t line_number = 0;
  std::size_t line_begin = 0;
  while (line_begin < text.size()) {
    std::size_t line_end = text.find('\n', line_begin);
    if (line_end == std::string_view::npos) line_end = text.size();
    const std::string_view line = text.substr(line_begin, line_end - line_begin);
    line_begin = line_end + 1;
    ++line_number;

    const std::vector<std::string_view> fields = splitFields(line);
    if (fields.empty() || fields.front().front() == '#') continue;

    const std::string where = std::string(source_name) + " line " + std::to_string(line_number) + ": ";
    StampedPose pose = parseLine(fields, where);
    if (!poses.empty()) {
      const std::int64_t step_ns = pose.t_ns - poses.back().t_ns;
      if (step_ns < 0) throw Error(where + "timestamp goes backwards by " + formatDuration(-step_ns));
      // Association and RPE key poses by stamp (as the TUM scripts' dicts do); two poses at one
      // instant are ambiguous, so refuse rather than silently keep one.
      if (step_ns == 0) throw Error(where + "timestamp repeats the previous pose's");
    }
    poses.push_back(pose);
  }
  return poses;
}

std::vector<StampedPose> readTum(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw Error("cannot open trajectory file '" + path.string() + "'");
  std::ostringstream contents;
  contents << file.rdbuf();
  if (file.bad()) throw Error("cannot read trajectory file '" + path.string() + "'");
  return parseTum(contents.str(), path.filename().string());
}

void writeTum(const std::filesystem::path& path, const std::vector<StampedPose>& poses) {
  std::ostringstream file;
  file << "# timestamp tx ty tz qx qy qz qw\n" << std::fixed << std::setprecision(9);
  for (const StampedPose& pose : poses) {
    const Eigen::Vector3d& t = pose.T_world_body.translation();
    const Eigen::Quaterniond& q = pose.T_world_body.quaternion();
    file << formatStamp(pose.t_ns) << ' ' << t.x() << ' ' << t.y() << ' ' << t.z() << ' ' << q.x() << ' ' << q.y()
         << ' ' << q.z() << ' ' << q.w() << '\n';
  }
  writeFileAtomically(path, file.view());
}

}  // namespace vifusion::eval
