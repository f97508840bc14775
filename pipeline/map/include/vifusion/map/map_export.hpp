#pragma once
// Reading the surfel map back to the host (map.ply, the daemon's shutdown file), chunk by chunk
// through a small staging buffer, so a 2 M-surfel map (96 MiB) never needs a map-sized readback
// copy in the arena: the default chunk of 65 536 surfels is 3 MiB of Readback memory.
//
// The surfel arrays are device-local, which on a discrete GPU is not host-visible, so they are
// never read through a mapped pointer: map_export.comp copies surfels [first, first + chunk) of
// the current array (bounded by the map state's surfel_count, read on the GPU) into the staging
// buffer; the host writes `first`, runs the sequence recorded once per parity, and copies the
// chunk out.
//
// Not on the per-frame path: each chunk is one blocking submission, and read() allocates the
// output. Call from the thread that owns the GPU, when no submission that writes the map is in
// flight (after the frame's wait): the host reads surfel_count from the map state.

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "vifusion/gpu/capacity_plan.hpp"
#include "vifusion/gpu/gpu_context.hpp"
#include "vifusion/gpu/memory_arena.hpp"
#include "vifusion/map/export_cpu.hpp"
#include "vifusion/map/map_buffers.hpp"

namespace vifusion::map {

struct ExportOptions {
  /// Surfels copied per submission. The staging buffer holds min(chunk_surfels, capacity)
  /// surfels of 48 bytes: the default is 3 MiB, against 96 MiB for a full 2 M-surfel map.
  std::uint32_t chunk_surfels = 65'536;
  std::uint32_t workgroups = 256;      ///< workgroups of the grid-stride copy
  std::uint32_t workgroup_size = 128;  ///< invocations per workgroup

  /// Throws vifusion::Error naming the field that is out of range.
  void validate() const;
};

class MapExport {
 public:
  /// Declares the staging buffer (Readback) and the parameter buffer (Upload, 16 bytes).
  /// `map` must outlive this object. Throws vifusion::Error on bad options.
  MapExport(gpu::GpuContext& context, gpu::CapacityPlan& plan, const MapBuffers& map,
            const ExportOptions& options = {});
  ~MapExport();
  MapExport(const MapExport&) = delete;
  MapExport& operator=(const MapExport&) = delete;

  /// Creates the kernel and, per surfel-array parity, its binding set and a command sequence
  /// recorded once.
  void build(const gpu::MemoryArena& arena);

  /// Surfels per chunk: min(options.chunk_surfels, map capacity).
  std::uint32_t chunkSurfels() const { return chunk_surfels_; }

  /// Copies the chunk of the current array (MapBuffers::current()) that starts at surfel
  /// `first_surfel` and returns it: exportChunkSize(surfel_count, {first_surfel, chunkSurfels()})
  /// surfels, empty past the end. The view points into the staging buffer and is valid until the
  /// next call.
  std::span<const Surfel> readChunk(std::uint32_t first_surfel);

  /// Called once per chunk, in order: `first_surfel` is the chunk's index in the map, `chunk`
  /// valid during the call only.
  using ChunkVisitor = std::function<void(std::uint32_t first_surfel, std::span<const Surfel> chunk)>;
  /// Visits the live surfels [0, surfel_count) chunk by chunk and returns surfel_count. Holds no
  /// more than one chunk on the host: the primitive for consumers that stream the map out.
  std::uint32_t visitChunks(const ChunkVisitor& visit);

  /// The live surfels [0, surfel_count) of the current array, in map order, bit for bit.
  /// Allocates: `out` grows to surfel_count entries (48 B each, 96 MiB for a full 2 M-surfel map)
  /// unless its capacity already suffices, so a caller that exports repeatedly can keep it.
  void read(std::vector<Surfel>& out);

  gpu::BufferId staging() const { return staging_; }  ///< chunkSurfels() surfels, host-readable

 private:
  struct Kernels;

  gpu::GpuContext& context_;
  const MapBuffers& map_;
  ExportOptions options_;
  std::uint32_t chunk_surfels_ = 0;
  gpu::BufferId params_;
  gpu::BufferId staging_;
  const gpu::MemoryArena* arena_ = nullptr;
  std::unique_ptr<Kernels> kernels_;
};

}  // namespace vifusion::map
