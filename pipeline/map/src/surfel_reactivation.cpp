#include "vifusion/map/surfel_reactivation.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "grid_stride.hpp"
#include "vifusion/gpu/compute_kernel.hpp"
#include "vifusion/shaders/spirv.hpp"

namespace vifusion::map {
namespace {

/// std430 header of map_reactivate_move.comp's MovePlan; the moves follow it.
struct MovePlanHeader {
  std::uint32_t move_count = 0;
  std::uint32_t pad[3] = {};
};

/// map_reactivate.comp's MarkedCount, padded to 16 bytes.
constexpr std::uint64_t kMarkedCountBytes = 16;

/// Workgroups of the grid-stride passes over the surfels and the moves.
constexpr std::uint32_t kWorkgroups = 2400;
constexpr std::uint32_t kWorkgroupSize = 128;

}  // namespace

ReactivateGates ReactivateGates::of(const FusionOptions& fusion, std::uint32_t capacity) {
  ReactivateGates gates;
  gates.max_depth_diff2_m2 = fusion.max_depth_diff_m * fusion.max_depth_diff_m;
  gates.min_normal_cos = std::cos(fusion.max_normal_angle_rad);
  gates.grazing_normal_z = fusion.grazing_normal_z;
  gates.capacity = capacity;
  return gates;
}

struct SurfelReactivation::Kernels {
  std::unique_ptr<gpu::ComputeKernel> reactivate;
  std::unique_ptr<gpu::ComputeKernel> move;
  gpu::BindingSet mark_sets[2];
  gpu::BindingSet move_sets[2];
  std::unique_ptr<gpu::CommandSequence> mark[2];  ///< mark, then copy the list for the plan
  std::unique_ptr<gpu::CommandSequence> moves[2];
};

SurfelReactivation::SurfelReactivation(gpu::GpuContext& context, gpu::CapacityPlan& plan, const MapBuffers& map,
                                       const ModelPrediction& inactive, const FusionOptions& fusion)
    : context_(context), map_(map), inactive_(inactive) {
  fusion.validate();
  const PinholeCamera& camera = inactive.camera(0);
  const auto pixels = static_cast<std::uint32_t>(camera.width) * static_cast<std::uint32_t>(camera.height);
  gates_ = ReactivateGates::of(fusion, kReactivatedPerPixel * pixels);
  const std::uint64_t list_bytes = std::uint64_t{gates_.capacity} * sizeof(std::uint32_t);
  gates_buffer_ = plan.addBuffer("map_reactivate.gates", sizeof(ReactivateGates), gpu::MemoryUse::Upload);
  // Host-visible: the kernel appends sparsely and the host plans from them, so nothing is copied.
  marked_count_ = plan.addBuffer("map_reactivate.count", kMarkedCountBytes, gpu::MemoryUse::Readback);
  marked_ = plan.addBuffer("map_reactivate.marked", list_bytes, gpu::MemoryUse::Readback);
  move_plan_ = plan.addBuffer("map_reactivate.moves",
                              sizeof(MovePlanHeader) + std::uint64_t{gates_.capacity} * sizeof(ReactivationMove),
                              gpu::MemoryUse::Upload);
  marked_slots_.resize(gates_.capacity);
}

SurfelReactivation::~SurfelReactivation() = default;

void SurfelReactivation::build(const gpu::MemoryArena& arena) {
  arena_ = &arena;
  std::memcpy(arena.buffer(gates_buffer_).mapped, &gates_, sizeof(gates_));
  kernels_ = std::make_unique<Kernels>();
  Kernels& k = *kernels_;
  // Both kernels: grid-stride over surfels or moves, one binding set per surfel-array parity.
  const auto create = [&](const char* name, std::span<const std::uint32_t> spirv, std::uint32_t storage_buffers) {
    gpu::KernelSpec spec;
    spec.name = name;
    spec.spirv = spirv;
    spec.storage_buffers = storage_buffers;
    spec.workgroup_size = {kWorkgroupSize, 1, 1};
    spec.max_binding_sets = 2;
    return gpu::ComputeKernel::create(context_, std::move(spec));
  };
  k.reactivate = create("map_reactivate", shaders::map_reactivate, 8);
  k.move = create("map_reactivate_move", shaders::map_reactivate_move, 3);
  const std::uint32_t groups = surfelWorkgroups(context_, kWorkgroups);
  const auto buffer = [&](gpu::BufferId id) { return &arena.buffer(id); };
  const ModelLevelBuffers& level0 = inactive_.level(0);
  for (int parity = 0; parity < 2; ++parity) {
    k.mark_sets[parity] = k.reactivate->bind(
        {buffer(map_.state()), buffer(inactive_.paramsBuffer()), buffer(map_.surfels(parity)), buffer(level0.vertices),
         buffer(level0.normals), buffer(gates_buffer_), buffer(marked_count_), buffer(marked_)});
    k.mark[parity] = gpu::CommandSequence::create(context_, "map reactivate " + std::to_string(parity));
    k.mark[parity]->record([&](gpu::CommandRecorder& recorder) {
      recorder.fillBuffer(arena.buffer(marked_count_), 0);
      recorder.computeBarrier();  // after the clear, the inactive prediction and earlier map writes
      recorder.dispatch(*k.reactivate, k.mark_sets[parity], {groups, 1, 1});
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

std::uint32_t SurfelReactivation::apply() {
  kernels_->mark[map_.current()]->run();

  const MapState state = map_.readState(*arena_);
  last_found_ = arena_->buffer(marked_count_).hostSpan<const std::uint32_t>()[0];
  const std::span<const std::uint32_t> marked =
      arena_->buffer(marked_).hostSpan<const std::uint32_t>().first(std::min(last_found_, gates_.capacity));
  std::byte* plan_bytes = arena_->buffer(move_plan_).mapped;
  const std::span<ReactivationMove> moves(reinterpret_cast<ReactivationMove*>(plan_bytes + sizeof(MovePlanHeader)),
                                          gates_.capacity);
  const ReactivationPlan plan = planReactivationMoves(marked, state.active_begin, marked_slots_, moves);
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

std::vector<std::uint32_t> reactivateInViewCpu(std::span<Surfel> surfels, const PredictionParams& params,
                                               ImageView<const Eigen::Vector4f> vertices,
                                               ImageView<const Eigen::Vector4f> normals, const ReactivateGates& gates) {
  std::vector<std::uint32_t> marked;
  const MapView& view = params.view;
  for (std::size_t i = 0; i < surfels.size() && marked.size() < gates.capacity; ++i) {
    Surfel& surfel = surfels[i];
    if (!isRenderedCpu(surfel, params)) continue;
    const Eigen::Vector3f p_C = transformPointCpu(view, surfel.position_confidence.head<3>());
    const Eigen::Vector3f n_C = rotateVectorCpu(view, surfel.normal_radius.head<3>());
    if (!(p_C.z() > params.min_depth_m && p_C.z() <= params.max_depth_m)) continue;
    const Eigen::Vector2f uv = projectPointCpu(view, p_C);
    const int x = static_cast<int>(std::floor(uv.x() + 0.5f));
    const int y = static_cast<int>(std::floor(uv.y() + 0.5f));
    if (x < 0 || y < 0 || x >= view.width || y >= view.height) continue;
    const Eigen::Vector4f& v = vertices(x, y);
    if (v.w() == 0.0f) continue;
    const Eigen::Vector4f& n = normals(x, y);
    const float dz = p_C.z() - v.z();
    const float v2 = (v.x() * v.x() + v.y() * v.y()) + v.z() * v.z();
    if (!((dz * dz) * v2 < gates.max_depth_diff2_m2 * (v.z() * v.z()))) continue;
    const float cos_angle = std::abs((n_C.x() * n.x() + n_C.y() * n.y()) + n_C.z() * n.z());
    if (!(cos_angle > gates.min_normal_cos || std::abs(n_C.z()) < gates.grazing_normal_z)) continue;
    surfel.colour_times.z() = static_cast<float>(view.frame);
    marked.push_back(static_cast<std::uint32_t>(i));
  }
  return marked;
}

}  // namespace vifusion::map
