#pragma once
// Reads a whole map file without loading it anywhere: every section decoded and checked (checksums, sizes,
// values), the surfels streamed through the reader's buffer. What `vifusion map info` prints, and the test
// that a file is sound before a service is pointed at it.

#include <array>
#include <cstdint>
#include <string>

#include "vifusion/core/rig_calibration.hpp"
#include "vifusion/mapfile/map_file_format.hpp"
#include "vifusion/mapfile/map_sections.hpp"

namespace vifusion::mapfile {

struct MapFileSummary {
  std::uint32_t format_version = 0;
  std::uint64_t file_bytes = 0;
  std::array<std::uint64_t, kSectionCount> section_bytes{};  ///< payload size per section [bytes]
  MapMeta meta;
  RigCalibration calibration;
  bool has_state = false;  ///< the estimator's state was saved (inertial modes)
  std::uint64_t trajectory_poses = 0;
  int keyframes = 0;  ///< 0 also when no database was saved
  SurfelsHeader surfels;
};

/// @throws vifusion::Error naming the file, the section and what is wrong, as MapFileReader does; a surfel
///         whose position, normal, radius or confidence is not finite is named by its index.
MapFileSummary checkMapFile(const std::string& path);

}  // namespace vifusion::mapfile
