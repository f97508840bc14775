#include "vifusion/map/surfel_reactivation.hpp"

#include <algorithm>
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

/// std430 header of map_reactivate_move.comp's MovePlan; the moves follow it.
struct MovePlanHeader {
  std::uint32_t move_count = 0;
  std::uint32_t pad[3] = {};
};

/// Workgroups of the grid-stride passes over the pixels and the moves (one invocation per pixel on a GPU at
/// 640×480; at most one move per pixel).
constexpr std::uint32_t kWorkgroups = 2400;
constexpr std::uint32_t kWorkgroupSize = 128;

}  // namespace

struct SurfelReactivation::Kernels {
  std::unique_ptr<gpu::ComputeKernel> reactivate;
  std::unique_ptr<gpu::ComputeKernel> move;
  gpu::BindingSet mark_sets[2];
  gpu::BindingSet move_sets[2];
  std::unique_ptr<gpu::CommandSequence> mark[2];  ///< mark, then copy the ids for the plan
  std::unique_ptr<gpu::CommandSequence> moves[2];
};

SurfelReactivation::SurfelReactivation(gpu::GpuContext& context, gpu::CapacityPlan& plan, const MapBuffers& map,
                                       const ModelPrediction& inactive)
    : context_(context), map_(map), ids_(inactive.splatIds()) {
  const PinholeCamera& camera = inactive.camera(0);
  pixels_ = static_cast<std::uint32_t>(camera.width) * static_cast<std::uint32_t>(camera.height);
  params_ = plan.addBuffer("map_reactivate.params", sizeof(ReactivateParams), gpu::MemoryUse::Upload);
  ids_readback_ =
      plan.addBuffer("map_reactivate.ids", std::uint64_t{pixels_} * sizeof(std::uint32_t), gpu::MemoryUse::Readback);
  move_plan_ =
      plan.addBuffer("map_reactivate.moves", sizeof(MovePlanHeader) + std::uint64_t{pixels_} * sizeof(ReactivationMove),
                     gpu::MemoryUse::Upload);
  marked_slots_.resize(pixels_);
}

SurfelReactivation::~SurfelReactivation() = default;

void SurfelReactivation::build(const gpu::MemoryArena& arena) {
  arena_ = &arena;
  kernels_ = std::make_unique<Kernels>();
  Kernels& k = *kernels_;
  // Both kernels: grid-stride over pixels or moves, one binding set per surfel-array parity.
  const auto create = [&](const char* name, std::span<const std::uint32_t> spirv, std::uint32_t storage_buffers) {
    gpu::KernelSpec spec;
    spec.name = name;
    spec.spirv = spirv;
    spec.storage_buffers = storage_buffers;
    spec.workgroup_size = {kWorkgroupSize, 1, 1};
    spec.max_binding_sets = 2;
    return gpu::ComputeKernel::create(context_, std::move(spec));
  };
  k.reactivate = create("map_reactivate", shaders::map_reactivate, 4);
  k.move = create("map_reactivate_move", shaders::map_reactivate_move, 3);
  const std::uint32_t groups = surfelWorkgroups(context_, kWorkgroups);
  const auto buffer = [&](gpu::BufferId id) { return &arena.buffer(id); };
  for (int parity = 0; parity < 2; ++parity) {
    k.mark_sets[parity] =
        k.reactivate->bind({buffer(map_.state()), buffer(map_.surfels(parity)), buffer(ids_), buffer(params_)});
    k.mark[parity] = gpu::CommandSequence::create(context_, "map reactivate " + std::to_string(parity));
    k.mark[parity]->record([&](gpu::CommandRecorder& recorder) {
      recorder.computeBarrier();  // after the inactive prediction and earlier map writes
      recorder.dispatch(*k.reactivate, k.mark_sets[parity], {groups, 1, 1});
      recorder.copyBuffer(arena.buffer(ids_), arena.buffer(ids_readback_),
                          std::uint64_t{pixels_} * sizeof(std::uint32_t));
      recorder.computeBarrier();
      recorder.hostReadBarrier();
    });
    k.move_sets[parity] =
        k.move->bind({buffer(map_.surfels(parity)), buffer(map_.surfels(parity ^ 1)), buffer(move_plan_)});
    k.moves[parity] = gpu::CommandSequence::create(context_, "map reactivate move " + std::to_string(parity));
    k.moves[parity]->record([&](gpu::CommandRecorder& recorder) {
      recorder.computeBarrier();
      recorder.dispatch(*k.move, k.move_sets[parity], {groups, 1, 1});
      recorder.computeBarrier();
    });
  }
}

std::uint32_t SurfelReactivation::apply(std::uint32_t frame) {
  const ReactivateParams params{pixels_, frame};
  std::memcpy(arena_->buffer(params_).mapped, &params, sizeof(params));
  kernels_->mark[map_.current()]->run();

  const MapState state = map_.readState(*arena_);
  const std::span<const std::uint32_t> ids = arena_->buffer(ids_readback_).hostSpan<const std::uint32_t>();
  std::byte* plan_bytes = arena_->buffer(move_plan_).mapped;
  const std::span<ReactivationMove> moves(reinterpret_cast<ReactivationMove*>(plan_bytes + sizeof(MovePlanHeader)),
                                          pixels_);
  const ReactivationPlan plan = planReactivationMoves(ids.first(pixels_), state.active_begin, marked_slots_, moves);
  if (plan.active_begin == state.active_begin) return 0;
  const MovePlanHeader header{plan.moves};
  std::memcpy(plan_bytes, &header, sizeof(header));
  if (plan.moves > 0) kernels_->moves[map_.current()]->run();
  map_.shrinkInactivePrefix(*arena_, plan.active_begin);
  return state.active_begin - plan.active_begin;
}

ReactivationPlan planReactivationMoves(std::span<const std::uint32_t> ids, std::uint32_t active_begin,
                                       std::span<std::uint32_t> scratch, std::span<ReactivationMove> moves) {
  std::size_t marked = 0;
  for (const std::uint32_t id : ids) {
    if (id < active_begin) scratch[marked++] = id;
  }
  const auto first = scratch.begin();
  std::sort(first, first + static_cast<std::ptrdiff_t>(marked));
  marked = static_cast<std::size_t>(std::unique(first, first + static_cast<std::ptrdiff_t>(marked)) - first);
  ReactivationPlan plan;
  plan.active_begin = active_begin - static_cast<std::uint32_t>(marked);
  // The marked slots below the new boundary pair up, in ascending order, with the unmarked slots above it.
  std::size_t above = static_cast<std::size_t>(
      std::lower_bound(first, first + static_cast<std::ptrdiff_t>(marked), plan.active_begin) - first);
  for (std::uint32_t slot = plan.active_begin; slot < active_begin; ++slot) {
    if (above < marked && scratch[above] == slot) {
      ++above;
      continue;
    }
    moves[plan.moves] = {scratch[plan.moves], slot};
    ++plan.moves;
  }
  return plan;
}

void applyReactivationMovesCpu(std::span<Surfel> current, std::span<Surfel> other,
                               std::span<const ReactivationMove> moves) {
  for (const ReactivationMove& move : moves) {
    const Surfel marked = current[move.marked_slot];
    const Surfel unmarked = current[move.unmarked_slot];
    current[move.marked_slot] = unmarked;
    other[move.marked_slot] = unmarked;
    current[move.unmarked_slot] = marked;
  }
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
