#pragma once
// Map export on the CPU: the reference of shaders/map_export.comp and the chunk rule the host and
// the shader share, plus the parameter block the host writes before each chunk (std430 mirror of
// ExportParams in the shader).

#include <cstdint>
#include <span>

#include "vifusion/map/surfel.hpp"

namespace vifusion::map {

/// ExportParams in map_export.comp.
struct ExportParams {
  std::uint32_t first_surfel = 0;   ///< index in the current surfel array of the chunk's first surfel
  std::uint32_t chunk_surfels = 0;  ///< surfels the staging buffer holds
  std::uint32_t pad[2] = {};
};
static_assert(sizeof(ExportParams) == 16);

/// Surfels in the chunk that starts at params.first_surfel of a map of `surfel_count` surfels:
/// min(chunk_surfels, surfel_count − first_surfel), 0 when first_surfel ≥ surfel_count.
std::uint32_t exportChunkSize(std::uint32_t surfel_count, const ExportParams& params);

/// map_export.comp: copies surfels [first_surfel, first_surfel + n) of `surfels` (the current
/// array, ≥ surfel_count entries) to staging[0, n), n = exportChunkSize(surfel_count, params), and
/// returns n. `staging` has ≥ n entries; entries from n on are left as they were.
std::uint32_t exportChunkCpu(std::span<const Surfel> surfels, std::uint32_t surfel_count, const ExportParams& params,
                             std::span<Surfel> staging);

}  // namespace vifusion::map
