#pragma once
// `vifusion map info FILE`: checks a map file the way a loader would (mapfile/map_file_check.hpp) and prints
// what it holds as one JSON object: format version, size per section, mode, frames, surfels, keyframes.

#include <string>

namespace vifusion::cli {

/// Returns 0 for a sound file. @throws vifusion::Error naming the file and the damaged section (exit 2).
int runMapInfo(const std::string& path);

}  // namespace vifusion::cli
