#pragma once
// bench_map_growth's per-frame record and its plot: ms/frame against the map's surfel count, one point per
// window of frames (wall and process CPU time), as a self-contained SVG file (no plotting library here).

#include <cstdint>
#include <string>
#include <vector>

#include "vifusion/slam/slam.hpp"

namespace vifusion::bench {

struct GrowthRow {
  std::uint32_t surfels = 0;
  std::uint32_t active_surfels = 0;
  bool lost = false;
  double wall_ms = 0.0;  ///< Slam::process, host wall time
  double cpu_ms = 0.0;   ///< the process's CPU time meanwhile (lavapipe's workers included)
  double preprocess_ms = 0.0, tracking_ms = 0.0, mapping_ms = 0.0, closure_ms = 0.0;
  slam::MapStageTimes stages;
};

/// Writes the plot to `path`: per window of `window` frames the mean wall and CPU ms/frame at the window's
/// mean surfel count, and the active range's mean. Throws vifusion::Error when the file cannot be written.
void writeGrowthSvg(const std::string& path, const std::vector<GrowthRow>& rows, int window, const std::string& title);

}  // namespace vifusion::bench
