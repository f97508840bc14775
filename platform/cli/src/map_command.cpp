#include "map_command.hpp"

#include <cstdio>
#include <nlohmann/json.hpp>

#include "vifusion/mapfile/map_file_check.hpp"

namespace vifusion::cli {

int runMapInfo(const std::string& path) {
  const mapfile::MapFileSummary summary = mapfile::checkMapFile(path);
  nlohmann::json sections = nlohmann::json::object();
  for (int s = 0; s < mapfile::kSectionCount; ++s) {
    const auto section = static_cast<mapfile::MapSection>(s);
    sections[std::string(mapfile::sectionName(section))] = summary.section_bytes[static_cast<std::size_t>(s)];
  }
  const nlohmann::json info = {
      {"file", path},
      {"format_version", summary.format_version},
      {"bytes", summary.file_bytes},
      {"section_bytes", sections},
      {"mode", summary.meta.mode},
      {"frames", summary.meta.frames},
      {"duration_s", 1e-9 * static_cast<double>(summary.meta.last_t_ns - summary.meta.first_t_ns)},
      {"camera", {{"width", summary.calibration.camera.width}, {"height", summary.calibration.camera.height}}},
      {"estimator_state", summary.has_state},
      {"trajectory_poses", summary.trajectory_poses},
      {"keyframes", summary.keyframes},
      {"surfels", summary.surfels.surfel_count},
      {"inactive_surfels", summary.surfels.active_begin}};
  std::printf("%s\n", info.dump().c_str());
  return 0;
}

}  // namespace vifusion::cli
