#pragma once
// A small but complete map for the map-file tests: every section holds something (a depth camera in the
// calibration, an inertial state, a trajectory, keyframes with images, surfels whose colour words are odd bit
// patterns), drawn from a seed; and where each section of a written file lies.

#include <cstdint>
#include <string>
#include <vector>

#include "vifusion/mapfile/map_file_format.hpp"
#include "vifusion/mapfile/map_file_reader.hpp"
#include "vifusion/mapfile/map_file_writer.hpp"
#include "vifusion/mapfile/map_sections.hpp"

namespace vifusion::mapfile::test {

struct SampleMap {
  MapMeta meta;
  RigCalibration calibration;
  std::optional<NavState> state;
  std::vector<StampedPose> trajectory;
  std::optional<loop::FernDatabase> keyframes;  ///< nullopt: relocalisation was off
  SurfelsHeader surfels_header;
  std::vector<float> surfels;  ///< surfel_count × kSurfelFloats

  explicit SampleMap(std::uint64_t seed, std::uint32_t surfel_count = 1000);
};

/// Writes the map as vifusion does (sections in order, surfels in chunks of `chunk_surfels`).
void writeSampleMap(const SampleMap& map, const std::string& path,
                    std::size_t buffer_bytes = MapFileWriter::kDefaultBufferBytes, std::size_t chunk_surfels = 256);

/// Reads every section back into a map and writes that map to `path_out`, through `buffer_bytes` buffers.
void copyMapFile(const std::string& path_in, const std::string& path_out, std::size_t buffer_bytes);

/// Where a section lies in a file: its header's offset and its payload's.
struct SectionPlace {
  MapSection section;
  std::uint64_t header_offset = 0;
  std::uint64_t payload_offset = 0;
  std::uint64_t payload_bytes = 0;
};
/// Walks the section headers of a sound file.
std::vector<SectionPlace> sectionPlaces(const std::vector<std::uint8_t>& file);

std::vector<std::uint8_t> readBytes(const std::string& path);
void writeBytes(const std::string& path, const std::vector<std::uint8_t>& bytes);
/// A fresh path in the test's temporary directory.
std::string temporaryPath(const std::string& name);

}  // namespace vifusion::mapfile::test
