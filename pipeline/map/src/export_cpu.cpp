#include "vifusion/map/export_cpu.hpp"

#include <algorithm>

namespace vifusion::map {

std::uint32_t exportChunkSize(std::uint32_t surfel_count, const ExportParams& params) {
  if (params.first_surfel >= surfel_count) return 0;
  return std::min(params.chunk_surfels, surfel_count - params.first_surfel);
}

std::uint32_t exportChunkCpu(std::span<const Surfel> surfels, std::uint32_t surfel_count, const ExportParams& params,
                             std::span<Surfel> staging) {
  const std::uint32_t n = exportChunkSize(surfel_count, params);
  std::copy_n(surfels.begin() + params.first_surfel, n, staging.begin());
  return n;
}

}  // namespace vifusion::map
