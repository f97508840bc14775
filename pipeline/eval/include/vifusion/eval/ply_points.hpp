#pragma once
// Vertex positions of a PLY file (ASCII or binary little-endian), whatever other per-vertex
// properties it carries: enough to score any reconstruction, ours (map.ply) or another system's.

#include <Eigen/Core>
#include <filesystem>
#include <vector>

namespace vifusion::eval {

/// @throws vifusion::Error naming the file and what is wrong: not PLY, unsupported format
/// (big-endian), no x/y/z vertex properties, list properties on vertices, truncated data.
std::vector<Eigen::Vector3d> readPlyPositions(const std::filesystem::path& path);

}  // namespace vifusion::eval
