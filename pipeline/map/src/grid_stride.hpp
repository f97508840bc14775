#pragma once
// Workgroups of the grid-stride passes over the surfels that the fusion records (map_index,
// map_fuse). The kernels loop over [0, surfel_count) whatever the grid, so this only tunes speed:
// GPUs want enough workgroups to fill every core, while on a CPU device (lavapipe: a workgroup is a
// loop over 8-wide slices on one of a handful of threads) a 1024-workgroup grid is mostly empty
// workgroups until the map holds 262k surfels, and they cost as much for an empty map as for a full
// one. Measured on 2 cores, CPU time per frame, 64 instead of 1024 workgroups:
//   map_index  7.3 → 3.1 ms at 320×240 (40k surfels), 12.4 → 9.3 ms at 640×480 (150k)
//   map_fuse   7.0 → 3.5 ms,                          11.8 → 12.4 ms
// The maintenance and prediction passes (128-wide, 256 and 512 workgroups) were measured too: a
// little faster at 320×240, 15-35 % slower at 640×480, so they keep their grids. Dispatching by the
// live count (indirect) would suit all of them; not done yet.

#include <algorithm>
#include <cstdint>

#include "vifusion/gpu/gpu_context.hpp"

namespace vifusion::map {

/// At most this many workgroups per grid-stride surfel pass on CPU devices.
inline constexpr std::uint32_t kCpuSurfelWorkgroups = 64;

/// `gpu_workgroups` on GPUs, at most kCpuSurfelWorkgroups on CPU devices.
inline std::uint32_t surfelWorkgroups(const gpu::GpuContext& context, std::uint32_t gpu_workgroups) {
  return context.features().device_type == VK_PHYSICAL_DEVICE_TYPE_CPU ? std::min(gpu_workgroups, kCpuSurfelWorkgroups)
                                                                       : gpu_workgroups;
}

}  // namespace vifusion::map
