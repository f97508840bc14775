// libFuzzer target: the PLY point reader of `vifusion eval --map` (eval::readPlyPositions) on arbitrary
// files, ASCII and binary. Errors must name the file; every point accepted is finite.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "fuzz_support.hpp"
#include "vifusion/eval/ply_points.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace vifusion;
  static const fuzz::ScratchFolder folder;
  const auto path = folder.write("map.ply", std::span<const std::uint8_t>(data, size));
  std::vector<Eigen::Vector3d> points;
  if (fuzz::parsedOrNamedError({"map.ply"}, [&] { points = eval::readPlyPositions(path); })) {
    for (const Eigen::Vector3d& point : points) fuzz::require(point.allFinite());
  }
  return 0;
}
