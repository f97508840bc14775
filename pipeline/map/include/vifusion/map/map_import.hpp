#pragma once
// Writing a loaded map (a map file, mapfile/map_sections.hpp) into the GPU's surfel array, chunk by chunk
// through a small host-written staging buffer, so a 2 M-surfel map (96 MiB) never needs a map-sized upload
// copy in the arena: the default chunk of 65 536 surfels is 3 MiB of Upload memory. The mirror of
// map_export.hpp, with its chunking options.
//
// The host fills the staging buffer (a file reader decodes straight into it), writes the chunk's place and
// runs the sequence recorded once per parity: map_import.comp copies the chunk into the current array. After
// the last chunk the map state says how many surfels there are and which frame last fused them, and the next
// frame visits the whole map (its maintenance sorts the active from the inactive ones by their times).
//
// Not on the per-frame path: each chunk is one blocking submission. Call from the thread that owns the GPU,
// before the first frame or between frames.

#include <cstdint>
#include <functional>
#include <memory>
#include <span>

#include "vifusion/gpu/capacity_plan.hpp"
#include "vifusion/gpu/gpu_context.hpp"
#include "vifusion/gpu/memory_arena.hpp"
#include "vifusion/map/import_cpu.hpp"
#include "vifusion/map/map_buffers.hpp"
#include "vifusion/map/map_export.hpp"

namespace vifusion::map {

class MapImport {
 public:
  /// Declares the staging buffer (Upload, min(chunk_surfels, capacity) surfels) and the parameter buffer.
  /// `map` must outlive this object. Throws vifusion::Error on bad options.
  MapImport(gpu::GpuContext& context, gpu::CapacityPlan& plan, MapBuffers& map, const ExportOptions& options = {});
  ~MapImport();
  MapImport(const MapImport&) = delete;
  MapImport& operator=(const MapImport&) = delete;

  /// Creates the kernel and, per surfel-array parity, its binding set and a command sequence recorded once.
  void build(const gpu::MemoryArena& arena);

  std::uint32_t chunkSurfels() const { return chunk_surfels_; }

  /// Called once per chunk, in order: fill `chunk` (the staging buffer's first chunk.size() surfels) with
  /// surfels [first_surfel, first_surfel + chunk.size()) of the map being loaded.
  using ChunkFiller = std::function<void(std::uint32_t first_surfel, std::span<Surfel> chunk)>;
  /// Replaces the map with `surfel_count` surfels from `fill`, last fused at frame `frame`, in the current
  /// array. @throws vifusion::Error when surfel_count exceeds the map's capacity (nothing is written then);
  /// an exception from `fill` propagates and leaves the map empty.
  void load(std::uint32_t surfel_count, std::uint32_t frame, const ChunkFiller& fill);

  gpu::BufferId staging() const { return staging_; }

 private:
  struct Kernels;

  gpu::GpuContext& context_;
  MapBuffers& map_;
  ExportOptions options_;
  std::uint32_t chunk_surfels_ = 0;
  gpu::BufferId params_;
  gpu::BufferId staging_;
  const gpu::MemoryArena* arena_ = nullptr;
  std::unique_ptr<Kernels> kernels_;
};

}  // namespace vifusion::map
