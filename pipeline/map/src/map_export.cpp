#include "vifusion/map/map_export.hpp"

#include <algorithm>
#include <cstring>
#include <string>

#include "chunk_copy.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/gpu/compute_kernel.hpp"
#include "vifusion/shaders/spirv.hpp"

namespace vifusion::map {
namespace {

std::string field(const char* name) { return std::string("map export option '") + name + "'"; }

}  // namespace

void ExportOptions::validate() const {
  if (chunk_surfels == 0) throw Error(field("chunk_surfels") + " must be ≥ 1");
  if (workgroups == 0) throw Error(field("workgroups") + " must be ≥ 1");
  if (workgroup_size == 0 || workgroup_size > 1024) throw Error(field("workgroup_size") + " must be in 1..1024");
}

struct MapExport::Kernels {
  std::unique_ptr<gpu::ComputeKernel> copy;
  gpu::BindingSet sets[2];
  std::unique_ptr<gpu::CommandSequence> sequences[2];  ///< per surfel-array parity
};

MapExport::MapExport(gpu::GpuContext& context, gpu::CapacityPlan& plan, const MapBuffers& map,
                     const ExportOptions& options)
    : context_(context), map_(map), options_(options) {
  options_.validate();
  chunk_surfels_ = std::min(options_.chunk_surfels, map.capacity());
  params_ = plan.addBuffer("map_export.params", sizeof(ExportParams), gpu::MemoryUse::Upload);
  staging_ = plan.addBuffer("map_export.staging", uint64_t{chunk_surfels_} * sizeof(Surfel), gpu::MemoryUse::Readback);
}

MapExport::~MapExport() = default;

void MapExport::build(const gpu::MemoryArena& arena) {
  arena_ = &arena;
  kernels_ = std::make_unique<Kernels>();
  Kernels& k = *kernels_;
  constexpr std::uint32_t kBindings = 4;  // state, params, source, staging (map_export.comp)
  k.copy = createChunkCopyKernel(context_, "map_export", shaders::map_export, kBindings, options_);
  const uint32_t groups = chunkCopyWorkgroups(options_, chunk_surfels_);
  auto buffer = [&](gpu::BufferId id) { return &arena.buffer(id); };
  for (int parity = 0; parity < 2; ++parity) {
    k.sets[parity] =
        k.copy->bind({buffer(map_.state()), buffer(params_), buffer(map_.surfels(parity)), buffer(staging_)});
    k.sequences[parity] = gpu::CommandSequence::create(context_, "map export " + std::to_string(parity));
    k.sequences[parity]->record([&](gpu::CommandRecorder& recorder) {
      // Orders the copy after earlier submissions' map writes (fusion, compaction) and after the
      // previous chunk's staging writes.
      recorder.computeBarrier();
      recorder.dispatch(*k.copy, k.sets[parity], {groups, 1, 1});
      recorder.hostReadBarrier();
    });
  }
}

std::span<const Surfel> MapExport::readChunk(std::uint32_t first_surfel) {
  const ExportParams params{first_surfel, chunk_surfels_};
  std::memcpy(arena_->buffer(params_).mapped, &params, sizeof(params));
  kernels_->sequences[map_.current()]->run();
  const std::uint32_t n = exportChunkSize(map_.readState(*arena_).surfel_count, params);
  return arena_->buffer(staging_).hostSpan<const Surfel>().first(n);
}

std::uint32_t MapExport::visitChunks(const ChunkVisitor& visit) {
  const std::uint32_t count = map_.readState(*arena_).surfel_count;
  // first < count ≤ 2^26 and chunk ≤ capacity ≤ 2^26: first + chunk never overflows.
  for (std::uint32_t first = 0; first < count; first += chunk_surfels_) visit(first, readChunk(first));
  return count;
}

void MapExport::read(std::vector<Surfel>& out) {
  out.clear();
  out.reserve(map_.readState(*arena_).surfel_count);
  visitChunks([&](std::uint32_t, std::span<const Surfel> chunk) { out.insert(out.end(), chunk.begin(), chunk.end()); });
}

}  // namespace vifusion::map
