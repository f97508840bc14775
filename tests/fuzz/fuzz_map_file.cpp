// libFuzzer target: the map file reader (pipeline/mapfile) on arbitrary files, through checkMapFile, which
// decodes and checks every section as `vifusion map info` and a service loading map_file do. Errors must name
// the file.

#include <cstddef>
#include <cstdint>
#include <span>

#include "fuzz_support.hpp"
#include "vifusion/mapfile/map_file_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace vifusion;
  static const fuzz::ScratchFolder folder;
  const std::string path = folder.write("saved.map", std::span<const std::uint8_t>(data, size)).string();
  mapfile::MapFileSummary summary;
  if (fuzz::parsedOrNamedError({"saved.map"}, [&] { summary = mapfile::checkMapFile(path); })) {
    fuzz::require(summary.file_bytes == size);
  }
  return 0;
}
