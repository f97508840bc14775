#include "vifusion/map/surfel_reactivation.hpp"

#include <cstring>
#include <string>

#include "grid_stride.hpp"
#include "vifusion/gpu/compute_kernel.hpp"
#include "vifusion/shaders/spirv.hpp"

namespace vifusion::map {
namespace {

/// std430 mirror of map_reactivate.comp's ReactivateParams.
struct ReactivateParams {
  std::uint32_t pixel_count = 0;
  std::uint32_t frame = 0;
  std::uint32_t pad[2] = {};
};

/// Workgroups of the grid-stride pass over the pixels (one invocation per pixel on a GPU at 640×480).
constexpr std::uint32_t kWorkgroups = 2400;
constexpr std::uint32_t kWorkgroupSize = 128;

}  // namespace

struct SurfelReactivation::Kernels {
  std::unique_ptr<gpu::ComputeKernel> reactivate;
  gpu::BindingSet sets[2];
  std::unique_ptr<gpu::CommandSequence> sequences[2];
};

SurfelReactivation::SurfelReactivation(gpu::GpuContext& context, gpu::CapacityPlan& plan, const MapBuffers& map,
                                       const ModelPrediction& inactive)
    : context_(context), map_(map), ids_(inactive.splatIds()) {
  const PinholeCamera& camera = inactive.camera(0);
  pixels_ = static_cast<std::uint32_t>(camera.width) * static_cast<std::uint32_t>(camera.height);
  params_ = plan.addBuffer("map_reactivate.params", sizeof(ReactivateParams), gpu::MemoryUse::Upload);
}

SurfelReactivation::~SurfelReactivation() = default;

void SurfelReactivation::build(const gpu::MemoryArena& arena) {
  arena_ = &arena;
  kernels_ = std::make_unique<Kernels>();
  Kernels& k = *kernels_;
  gpu::KernelSpec spec;
  spec.name = "map_reactivate";
  spec.spirv = shaders::map_reactivate;
  spec.storage_buffers = 4;
  spec.workgroup_size = {kWorkgroupSize, 1, 1};
  spec.max_binding_sets = 2;
  k.reactivate = gpu::ComputeKernel::create(context_, std::move(spec));
  const std::uint32_t groups = surfelWorkgroups(context_, kWorkgroups);
  const auto buffer = [&](gpu::BufferId id) { return &arena.buffer(id); };
  for (int parity = 0; parity < 2; ++parity) {
    k.sets[parity] =
        k.reactivate->bind({buffer(map_.state()), buffer(map_.surfels(parity)), buffer(ids_), buffer(params_)});
    k.sequences[parity] = gpu::CommandSequence::create(context_, "map reactivate " + std::to_string(parity));
    k.sequences[parity]->record([&](gpu::CommandRecorder& recorder) {
      recorder.computeBarrier();  // after the inactive prediction and earlier map writes
      recorder.dispatch(*k.reactivate, k.sets[parity], {groups, 1, 1});
      recorder.computeBarrier();
    });
  }
}

void SurfelReactivation::apply(std::uint32_t frame) {
  const ReactivateParams params{pixels_, frame};
  std::memcpy(arena_->buffer(params_).mapped, &params, sizeof(params));
  kernels_->sequences[map_.current()]->run();
  // Surfels of the inactive prefix are active now (and only in the current array).
  map_.visitWholeMapNextFrame(*arena_);
}

void reactivateSurfelsCpu(std::span<Surfel> surfels, ImageView<const std::uint32_t> ids, std::uint32_t frame) {
  for (int y = 0; y < ids.height; ++y) {
    for (int x = 0; x < ids.width; ++x) {
      const std::uint32_t id = ids(x, y);
      if (id < surfels.size()) surfels[id].colour_times.z() = static_cast<float>(frame);
    }
  }
}

}  // namespace vifusion::map
