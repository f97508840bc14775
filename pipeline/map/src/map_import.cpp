#include "vifusion/map/map_import.hpp"

#include <algorithm>
#include <cstring>
#include <string>

#include "chunk_copy.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/gpu/compute_kernel.hpp"
#include "vifusion/shaders/spirv.hpp"

namespace vifusion::map {

struct MapImport::Kernels {
  std::unique_ptr<gpu::ComputeKernel> copy;
  gpu::BindingSet sets[2];
  std::unique_ptr<gpu::CommandSequence> sequences[2];  ///< per surfel-array parity
};

MapImport::MapImport(gpu::GpuContext& context, gpu::CapacityPlan& plan, MapBuffers& map, const ExportOptions& options)
    : context_(context), map_(map), options_(options) {
  options_.validate();
  chunk_surfels_ = std::min(options_.chunk_surfels, map.capacity());
  params_ = plan.addBuffer("map_import.params", sizeof(ImportParams), gpu::MemoryUse::Upload);
  staging_ = plan.addBuffer("map_import.staging", uint64_t{chunk_surfels_} * sizeof(Surfel), gpu::MemoryUse::Upload);
}

MapImport::~MapImport() = default;

void MapImport::build(const gpu::MemoryArena& arena) {
  arena_ = &arena;
  kernels_ = std::make_unique<Kernels>();
  Kernels& k = *kernels_;
  constexpr std::uint32_t kBindings = 3;  // params, staging, destination (map_import.comp)
  k.copy = createChunkCopyKernel(context_, "map_import", shaders::map_import, kBindings, options_);
  const uint32_t groups = chunkCopyWorkgroups(options_, chunk_surfels_);
  auto buffer = [&](gpu::BufferId id) { return &arena.buffer(id); };
  for (int parity = 0; parity < 2; ++parity) {
    k.sets[parity] = k.copy->bind({buffer(params_), buffer(staging_), buffer(map_.surfels(parity))});
    k.sequences[parity] = gpu::CommandSequence::create(context_, "map import " + std::to_string(parity));
    k.sequences[parity]->record([&](gpu::CommandRecorder& recorder) {
      // After earlier submissions' use of the array; the next submission's passes read the chunk.
      recorder.computeBarrier();
      recorder.dispatch(*k.copy, k.sets[parity], {groups, 1, 1});
      recorder.computeBarrier();
    });
  }
}

void MapImport::load(std::uint32_t surfel_count, std::uint32_t frame, const ChunkFiller& fill) {
  if (surfel_count > map_.capacity()) {
    throw Error("map import: " + std::to_string(surfel_count) + " surfels do not fit a map of capacity " +
                std::to_string(map_.capacity()));
  }
  map_.setLoaded(*arena_, 0, 0);  // empty until every chunk is in (in the array current now)
  const std::span<Surfel> staging = arena_->buffer(staging_).hostSpan<Surfel>().first(chunk_surfels_);
  for (std::uint32_t first = 0; first < surfel_count; first += chunk_surfels_) {
    const ImportParams params{first, std::min(chunk_surfels_, surfel_count - first)};
    fill(first, staging.first(params.count));
    std::memcpy(arena_->buffer(params_).mapped, &params, sizeof(params));
    kernels_->sequences[map_.current()]->run();
  }
  map_.setLoaded(*arena_, surfel_count, frame);
}

}  // namespace vifusion::map
