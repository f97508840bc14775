#include "vifusion/map/map_maintenance.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "vifusion/core/error.hpp"
#include "vifusion/shaders/spirv.hpp"

namespace vifusion::map {
namespace {

std::string field(const char* name) { return std::string("maintenance option '") + name + "'"; }

/// Workgroup size of map_compact_scan; each invocation scans 4 elements.
constexpr std::uint32_t kScanWorkgroupSize = kCompactTileSize / 4;

std::uint32_t tilesOf(std::uint32_t n) { return std::max(1u, (n + kCompactTileSize - 1) / kCompactTileSize); }

/// Push constants of map_compact_scan.comp and map_compact_add.comp.
struct LevelPush {
  std::uint32_t level = 0;
};

}  // namespace

void MaintenanceOptions::validate() const {
  if (!(free_space_margin_m >= 0.0f)) throw Error(field("free_space_margin_m") + " must be ≥ 0");
  if (!(facing_min_abs_nz >= 0.0f && facing_min_abs_nz < 1.0f))
    throw Error(field("facing_min_abs_nz") + " must be in [0, 1)");
  if (free_space_min_neighbours == 0 || free_space_min_neighbours > 8) {
    throw Error(field("free_space_min_neighbours") + " must be in 1..8 (other surfels of a 3×3 window)");
  }
  if (!(full_fraction > 0.0f && full_fraction <= 1.0f)) throw Error(field("full_fraction") + " must be in (0, 1]");
  if (!(eviction_confidence >= 0.0f)) throw Error(field("eviction_confidence") + " must be ≥ 0");
  if (workgroups == 0) throw Error(field("workgroups") + " must be ≥ 1");
  if (workgroup_size == 0 || workgroup_size > 1024) throw Error(field("workgroup_size") + " must be in 1..1024");
}

struct MapMaintenance::Kernels {
  std::unique_ptr<gpu::ComputeKernel> cleanup, scan, add, scatter, prefix, finish;
  gpu::BindingSet cleanup_sets[2], scatter_sets[2], prefix_sets[2], finish_set;
  std::vector<gpu::BindingSet> scan_sets[2];  ///< per chain (keep, retire), per level
  std::vector<gpu::BindingSet> add_sets[2];   ///< per chain, per level 1..L−1
  std::uint32_t surfel_groups = 1;
};

MapMaintenance::ScanChain MapMaintenance::declareChain(gpu::CapacityPlan& plan, const char* name) {
  const std::string prefix = std::string("maintenance.") + name;
  ScanChain chain;
  chain.flags = plan.addBuffer(prefix + ".flags", uint64_t{level_sizes_[0]} * 4, gpu::MemoryUse::DeviceLocal);
  for (std::size_t l = 0; l < level_sizes_.size(); ++l) {
    const std::string level = std::to_string(l);
    chain.offsets.push_back(
        plan.addBuffer(prefix + ".offsets.l" + level, uint64_t{level_sizes_[l]} * 4, gpu::MemoryUse::DeviceLocal));
    const uint64_t sums = l + 1 < level_sizes_.size() ? level_sizes_[l + 1] : 1;  // the last: the total
    chain.tile_sums.push_back(plan.addBuffer(prefix + ".tile_sums.l" + level, sums * 4, gpu::MemoryUse::DeviceLocal));
  }
  return chain;
}

MapMaintenance::MapMaintenance(gpu::GpuContext& context, gpu::CapacityPlan& plan, const MapBuffers& map,
                               const PinholeCamera& camera, const MaintenanceOptions& options)
    : context_(context),
      options_(options),
      map_options_(map.options()),
      camera_(camera),
      state_(map.state()),
      index_depth_(map.indexDepth()),
      index_id_(map.indexId()),
      map_(map) {
  options_.validate();
  if (camera.width != map.width() || camera.height != map.height()) {
    throw Error("map maintenance: camera is " + std::to_string(camera.width) + "x" + std::to_string(camera.height) +
                ", the map's index map " + std::to_string(map.width()) + "x" + std::to_string(map.height()));
  }
  surfels_[0] = map.surfels(0);
  surfels_[1] = map.surfels(1);
  const std::uint32_t capacity = map_options_.capacity;
  params_ = plan.addBuffer("maintenance.params", sizeof(CleanupParams), gpu::MemoryUse::Upload);
  stats_ = plan.addBuffer("maintenance.stats", sizeof(MaintenanceStats), gpu::MemoryUse::Readback);
  // Level 0 is the flags; level k+1 holds the tile totals of level k, until a level fits one tile.
  // At least one level above 0, so the scatter always has tile offsets to add.
  level_sizes_.push_back(capacity);
  do {
    level_sizes_.push_back(tilesOf(level_sizes_.back()));
  } while (level_sizes_.back() > kCompactTileSize);
  keep_ = declareChain(plan, "keep");
  retire_ = declareChain(plan, "retire");
}

MapMaintenance::~MapMaintenance() = default;

void MapMaintenance::build(const gpu::MemoryArena& arena) {
  arena_ = &arena;
  kernels_ = std::make_unique<Kernels>();
  Kernels& k = *kernels_;
  const std::array<uint32_t, 3> wg = {options_.workgroup_size, 1, 1};
  const auto levels = static_cast<uint32_t>(level_sizes_.size());
  auto make = [&](const char* name, std::span<const uint32_t> spirv, uint32_t buffers, uint32_t push_bytes,
                  std::array<uint32_t, 3> workgroup, uint32_t sets) {
    gpu::KernelSpec spec;
    spec.name = name;
    spec.spirv = spirv;
    spec.storage_buffers = buffers;
    spec.push_constant_bytes = push_bytes;
    spec.workgroup_size = workgroup;
    spec.constants = {{3, kCompactTileSize}};
    spec.max_binding_sets = std::max(1u, sets);
    return gpu::ComputeKernel::create(context_, std::move(spec));
  };
  k.cleanup = make("map_cleanup", shaders::map_cleanup, 8, 0, wg, 2);
  k.scan =
      make("map_compact_scan", shaders::map_compact_scan, 4, sizeof(LevelPush), {kScanWorkgroupSize, 1, 1}, 2 * levels);
  k.add = make("map_compact_add", shaders::map_compact_add, 3, sizeof(LevelPush), wg, 2 * (levels - 2));
  k.scatter = make("map_compact_scatter", shaders::map_compact_scatter, 10, 0, wg, 2);
  k.prefix = make("map_compact_prefix", shaders::map_compact_prefix, 4, 0, wg, 2);
  k.finish = make("map_compact_finish", shaders::map_compact_finish, 4, 0, {1, 1, 1}, 1);

  const uint64_t capacity_groups =
      (uint64_t{map_options_.capacity} + options_.workgroup_size - 1) / options_.workgroup_size;
  k.surfel_groups = static_cast<uint32_t>(std::min<uint64_t>(options_.workgroups, capacity_groups));

  auto buffer = [&](gpu::BufferId id) { return &arena.buffer(id); };
  for (int parity = 0; parity < 2; ++parity) {
    k.cleanup_sets[parity] =
        k.cleanup->bind({buffer(state_), buffer(params_), buffer(surfels_[parity]), buffer(index_depth_),
                         buffer(index_id_), buffer(keep_.flags), buffer(stats_), buffer(retire_.flags)});
    k.scatter_sets[parity] =
        k.scatter->bind({buffer(state_), buffer(keep_.flags), buffer(keep_.offsets[0]), buffer(keep_.offsets[1]),
                         buffer(surfels_[parity]), buffer(surfels_[parity ^ 1]), buffer(retire_.flags),
                         buffer(retire_.offsets[0]), buffer(retire_.offsets[1]), buffer(retire_.tile_sums.back())});
    k.prefix_sets[parity] = k.prefix->bind(
        {buffer(state_), buffer(retire_.tile_sums.back()), buffer(surfels_[parity ^ 1]), buffer(surfels_[parity])});
  }
  const ScanChain* chains[2] = {&keep_, &retire_};
  for (int c = 0; c < 2; ++c) {
    const ScanChain& chain = *chains[c];
    for (uint32_t l = 0; l < levels; ++l) {
      const gpu::BufferId values = l == 0 ? chain.flags : chain.tile_sums[l - 1];
      k.scan_sets[c].push_back(
          k.scan->bind({buffer(state_), buffer(values), buffer(chain.offsets[l]), buffer(chain.tile_sums[l])}));
    }
    for (uint32_t l = 1; l + 1 < levels; ++l) {
      k.add_sets[c].push_back(k.add->bind({buffer(state_), buffer(chain.offsets[l]), buffer(chain.offsets[l + 1])}));
    }
  }
  k.finish_set = k.finish->bind(
      {buffer(state_), buffer(keep_.tile_sums.back()), buffer(stats_), buffer(retire_.tile_sums.back())});
}

std::uint32_t MapMaintenance::fullCount() const {
  return static_cast<std::uint32_t>(std::floor(double{options_.full_fraction} * map_options_.capacity));
}

CleanupParams MapMaintenance::makeParams(const SE3d& T_C_W, std::uint32_t frame) const {
  CleanupParams params;
  params.view = MapView::make(T_C_W, camera_, frame);
  params.confidence_threshold = map_options_.confidence_threshold;
  params.time_window_frames = map_options_.time_window_frames;
  params.unstable_max_age_frames = map_options_.unstable_max_age_frames;
  params.max_depth_m = map_options_.max_depth_m;
  params.free_space_margin_m = options_.free_space_margin_m;
  params.facing_min_abs_nz = options_.facing_min_abs_nz;
  params.free_space_min_neighbours = options_.free_space_min_neighbours;
  params.full_count = fullCount();
  params.eviction_confidence = options_.eviction_confidence;
  params.eviction_age_frames = eviction_age_frames_;
  return params;
}

void MapMaintenance::setView(const SE3d& T_C_W, std::uint32_t frame) {
  MapState state;
  std::memcpy(&state, arena_->buffer(state_).mapped, sizeof(state));
  eviction_age_frames_ =
      nextEvictionAge(eviction_age_frames_, state.surfel_count, fullCount(), frame, map_options_.time_window_frames);
  if (state.surfel_count > fullCount()) map_.visitWholeMapNextFrame(*arena_);
  const CleanupParams params = makeParams(T_C_W, frame);
  std::memcpy(arena_->buffer(params_).mapped, &params, sizeof(params));
}

void MapMaintenance::record(gpu::CommandRecorder& recorder, int parity) const {
  recordCleanup(recorder, parity);
  recordCompaction(recorder, parity);
}

void MapMaintenance::recordCleanup(gpu::CommandRecorder& recorder, int parity) const {
  const Kernels& k = *kernels_;
  recorder.fillBuffer(arena_->buffer(stats_), 0u);
  recorder.computeBarrier();
  recorder.dispatch(*k.cleanup, k.cleanup_sets[parity & 1], {k.surfel_groups, 1, 1});
  recorder.computeBarrier();
}

void MapMaintenance::recordCompaction(gpu::CommandRecorder& recorder, int parity) const {
  const Kernels& k = *kernels_;
  const auto levels = static_cast<uint32_t>(level_sizes_.size());
  // Both chains level by level: a level's two dispatches are independent of each other.
  for (uint32_t l = 0; l < levels; ++l) {
    const uint32_t groups = std::min(options_.workgroups, tilesOf(level_sizes_[l]));
    for (int c = 0; c < 2; ++c) recorder.dispatch(*k.scan, k.scan_sets[c][l], {groups, 1, 1}, LevelPush{l});
    recorder.computeBarrier();
  }
  for (uint32_t l = levels - 2; l >= 1; --l) {
    const uint64_t groups = (uint64_t{level_sizes_[l]} + options_.workgroup_size - 1) / options_.workgroup_size;
    for (int c = 0; c < 2; ++c) {
      recorder.dispatch(*k.add, k.add_sets[c][l - 1],
                        {static_cast<uint32_t>(std::min<uint64_t>(options_.workgroups, groups)), 1, 1}, LevelPush{l});
    }
    recorder.computeBarrier();
  }
  recorder.dispatch(*k.scatter, k.scatter_sets[parity & 1], {k.surfel_groups, 1, 1});
  recorder.computeBarrier();
  recorder.dispatch(*k.prefix, k.prefix_sets[parity & 1], {k.surfel_groups, 1, 1});
  recorder.computeBarrier();
  recorder.dispatch(*k.finish, k.finish_set, {1, 1, 1});
  recorder.computeBarrier();
  recorder.hostReadBarrier();
}

MaintenanceStats MapMaintenance::stats() const {
  MaintenanceStats stats;
  std::memcpy(&stats, arena_->buffer(stats_).mapped, sizeof(stats));
  return stats;
}

}  // namespace vifusion::map
