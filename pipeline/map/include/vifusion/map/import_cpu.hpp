#pragma once
// Map import on the CPU: the reference of shaders/map_import.comp and the parameter block the host writes
// before each chunk (std430 mirror of ImportParams in the shader).

#include <cstdint>
#include <span>

#include "vifusion/map/surfel.hpp"

namespace vifusion::map {

/// ImportParams in map_import.comp.
struct ImportParams {
  std::uint32_t first_surfel = 0;  ///< index in the current surfel array of the chunk's first surfel
  std::uint32_t count = 0;         ///< surfels in the chunk, ≤ the staging buffer's
  std::uint32_t pad[2] = {};
};
static_assert(sizeof(ImportParams) == 16);

/// map_import.comp: writes staging[0, count) to surfels[first_surfel, first_surfel + count). `surfels` holds at
/// least first_surfel + count entries; the others are left as they were.
void importChunkCpu(std::span<const Surfel> staging, const ImportParams& params, std::span<Surfel> surfels);

}  // namespace vifusion::map
