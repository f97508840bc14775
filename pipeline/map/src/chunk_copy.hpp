#pragma once
// The grid-stride chunk copy that moves surfels between the map and a small host-visible staging buffer, in
// either direction (map_export.comp to the host, map_import.comp from it): one kernel shape, one grid rule.

#include <algorithm>
#include <cstdint>
#include <memory>
#include <span>

#include "vifusion/gpu/compute_kernel.hpp"
#include "vifusion/gpu/gpu_context.hpp"
#include "vifusion/map/map_export.hpp"

namespace vifusion::map {

/// The copy kernel `name` from `spirv` with `storage_buffers` bindings, its workgroup size from `options`,
/// bound once per surfel-array parity.
inline std::unique_ptr<gpu::ComputeKernel> createChunkCopyKernel(gpu::GpuContext& context, const char* name,
                                                                 std::span<const std::uint32_t> spirv,
                                                                 std::uint32_t storage_buffers,
                                                                 const ExportOptions& options) {
  gpu::KernelSpec spec;
  spec.name = name;
  spec.spirv = spirv;
  spec.storage_buffers = storage_buffers;
  spec.workgroup_size = {options.workgroup_size, 1, 1};
  spec.max_binding_sets = 2;
  return gpu::ComputeKernel::create(context, std::move(spec));
}

/// Workgroups of the copy: options.workgroups, fewer when a chunk needs fewer.
inline std::uint32_t chunkCopyWorkgroups(const ExportOptions& options, std::uint32_t chunk_surfels) {
  return std::min(options.workgroups, (chunk_surfels + options.workgroup_size - 1) / options.workgroup_size);
}

}  // namespace vifusion::map
