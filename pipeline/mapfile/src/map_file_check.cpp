#include "vifusion/mapfile/map_file_check.hpp"

#include <cmath>
#include <vector>

#include "vifusion/mapfile/map_file_reader.hpp"

namespace vifusion::mapfile {
namespace {

/// Surfels decoded per read: 1 MiB of floats at a time.
constexpr std::size_t kSurfelsPerChunk = (std::size_t{1} << 20) / (kSurfelFloats * sizeof(float));
/// The record's words holding the colour bits (map/surfel.hpp: colour_times.x): any bit pattern is valid there.
constexpr std::size_t kColourWord = 8;

}  // namespace

MapFileSummary checkMapFile(const std::string& path) {
  MapFileReader reader(path);
  MapFileSummary summary;
  summary.format_version = reader.formatVersion();
  summary.file_bytes = reader.fileBytes();
  summary.meta = readMeta(reader);
  summary.calibration = readCalibration(reader);
  summary.has_state = readState(reader).has_value();
  summary.trajectory_poses = readTrajectory(reader).size();
  const std::optional<loop::FernDatabase> keyframes = readKeyframes(reader);
  summary.keyframes = keyframes ? keyframes->size() : 0;
  summary.surfels = beginSurfels(reader);
  std::vector<float> chunk(kSurfelsPerChunk * kSurfelFloats);
  for (std::uint32_t first = 0; first < summary.surfels.surfel_count;) {
    const std::size_t n = std::min<std::size_t>(kSurfelsPerChunk, summary.surfels.surfel_count - first);
    reader.getF32s({chunk.data(), n * kSurfelFloats});
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t word = 0; word < kSurfelFloats; ++word)
        if (word != kColourWord && !std::isfinite(chunk[i * kSurfelFloats + word]))
          reader.fail("surfel " + std::to_string(first + i) + " has a value that is not finite");
    first += static_cast<std::uint32_t>(n);
  }
  reader.endSection();
  reader.finish();
  for (int s = 0; s < kSectionCount; ++s)
    summary.section_bytes[static_cast<std::size_t>(s)] = reader.sectionBytes(static_cast<MapSection>(s));
  return summary;
}

}  // namespace vifusion::mapfile
