#pragma once
// The surfel map as a PLY point cloud (map.ply: `vifusion run` output, the daemon's shutdown
// file), readable by eval::readPlyPositions, MeshLab, CloudCompare and Open3D.
//
// Format: binary_little_endian 1.0, one element `vertex` with exactly these properties, in this
// order (35 bytes per vertex, no padding):
//   float x, y, z           position in the map world W [m]
//   float nx, ny, nz        unit normal in W
//   uchar red, green, blue  colour, 0..255 (the surfel's packed RGB8)
//   float radius            disk radius [m]
//   float confidence        accumulated fusion weight (stable when ≥ MapOptions::confidence_threshold)
// The header's comments name the frame and units and the min_confidence the file was written with.
// Vertices keep the map's order.

#include <cstddef>
#include <filesystem>
#include <span>

#include "vifusion/map/surfel.hpp"

namespace vifusion::map {

struct SurfelPlyOptions {
  /// Surfels whose confidence is below this are left out; 0 (the default) writes every surfel.
  float min_confidence = 0.0f;

  /// Throws vifusion::Error naming the field that is out of range.
  void validate() const;

  /// ElasticFusion's export: the stable surfels only (confidence ≥ the map's threshold). The
  /// deliberate default of `vifusion run` and the daemon: unstable surfels are mostly single-view
  /// noise and free-space outliers that tracking never renders either, so they would only add
  /// error to a scored reconstruction. Pass min_confidence = 0 to keep everything.
  static SurfelPlyOptions stableOnly(const MapOptions& map);
};

/// Writes the surfels with confidence ≥ options.min_confidence to `path` and returns how many.
/// Atomic: the file is written as "<path>.tmp" in the same directory, flushed to disk and renamed
/// over `path`, so an interrupted or failed write leaves the previous file intact (and no
/// temporary file behind, except after a crash). Throws vifusion::Error naming the path and what
/// failed (bad options, cannot create, write, flush, rename).
std::size_t writeSurfelPly(const std::filesystem::path& path, std::span<const Surfel> surfels,
                           const SurfelPlyOptions& options = {});

}  // namespace vifusion::map
