#include "vifusion/map/import_cpu.hpp"

#include <algorithm>

namespace vifusion::map {

void importChunkCpu(std::span<const Surfel> staging, const ImportParams& params, std::span<Surfel> surfels) {
  std::copy_n(staging.begin(), params.count, surfels.begin() + params.first_surfel);
}

}  // namespace vifusion::map
