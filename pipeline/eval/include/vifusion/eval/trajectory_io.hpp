#pragma once
// TUM RGB-D trajectory files: one pose per line, "t tx ty tz qx qy qz qw" with t in seconds, the
// translation in metres and the orientation as a Hamilton quaternion, T_world_body. Lines starting
// with '#' and blank lines are skipped; spaces, commas and tabs all separate fields (associate.py).

#include <cstdint>
#include <filesystem>
#include <string_view>
#include <vector>

#include "vifusion/core/se3.hpp"

namespace vifusion::eval {

struct StampedPose {
  std::int64_t t_ns = 0;  ///< Stamp [ns], exactly the decimal written in the file.
  SE3d T_world_body;
};

/// Parses the text of a TUM trajectory. `source_name` prefixes every error message, e.g.
/// "gt.txt line 12: expected 8 numbers, found 7". Rejects non-finite fields, stamps that do not
/// strictly increase, and quaternions whose norm is more than 1e-3 from 1 (smaller deviations are
/// rounding in the file and are normalised away).
/// @throws vifusion::Error on the first malformed line.
std::vector<StampedPose> parseTum(std::string_view text, std::string_view source_name);

/// Reads and parses a TUM trajectory file; errors name the file by its filename.
/// @throws vifusion::Error if the file cannot be read or a line is malformed.
std::vector<StampedPose> readTum(const std::filesystem::path& path);

/// Writes poses in TUM format with a '#' header; stamps are written exactly (9 decimals) and poses
/// with 9 significant digits after the point, enough to round-trip at sub-micrometre precision.
/// Written atomically (core/atomic_file.hpp). @throws vifusion::Error if the file cannot be written.
void writeTum(const std::filesystem::path& path, const std::vector<StampedPose>& poses);

}  // namespace vifusion::eval
