#include "vifusion/map/model_prediction.hpp"

#include <algorithm>
#include <cstring>
#include <string>

#include "vifusion/core/error.hpp"
#include "vifusion/shaders/spirv.hpp"

namespace vifusion::map {
namespace {

std::string field(const char* name) { return std::string("prediction option '") + name + "'"; }

/// Push constants of map_pyramid_subsample.comp.
struct SubsamplePush {
  std::int32_t src_width = 0;   ///< [px]
  std::int32_t dst_width = 0;   ///< [px]
  std::int32_t dst_height = 0;  ///< [px]
  std::int32_t step = 0;        ///< 2^level
};

}  // namespace

void PredictionOptions::validate() const {
  if (levels < 1 || levels > 8) throw Error(field("levels") + " must be in 1..8");
  if (surfels != PredictedSurfels::kActive && surfels != PredictedSurfels::kInactive &&
      surfels != PredictedSurfels::kStable) {
    throw Error(field("surfels") + " must be kActive, kInactive or kStable");
  }
  if (!(min_depth_m > 0.0f)) throw Error(field("min_depth_m") + " must be > 0");
  if (max_half_footprint_px < 0 || max_half_footprint_px > 15)
    throw Error(field("max_half_footprint_px") + " must be in 0..15");
  if (surfel_workgroups == 0) throw Error(field("surfel_workgroups") + " must be ≥ 1");
  if (surfel_workgroup_size == 0 || surfel_workgroup_size > 1024)
    throw Error(field("surfel_workgroup_size") + " must be in 1..1024");
  if (image_workgroup_size == 0 || image_workgroup_size > 32)
    throw Error(field("image_workgroup_size") + " must be in 1..32");
}

struct ModelPrediction::Kernels {
  std::unique_ptr<gpu::ComputeKernel> depth, id, attributes, subsample;
  gpu::BindingSet depth_sets[2], id_sets[2], attribute_sets[2];
  std::vector<gpu::BindingSet> subsample_sets;  ///< one per level ≥ 1
  std::uint32_t splat_groups = 1;
};

ModelPrediction::ModelPrediction(gpu::GpuContext& context, gpu::CapacityPlan& plan, const MapBuffers& map,
                                 const PinholeCamera& camera, const PredictionOptions& options)
    : context_(context), options_(options), map_options_(map.options()), state_(map.state()) {
  options_.validate();
  if (camera.width != map.width() || camera.height != map.height()) {
    throw Error("model prediction: camera is " + std::to_string(camera.width) + "x" + std::to_string(camera.height) +
                ", the map's index map " + std::to_string(map.width()) + "x" + std::to_string(map.height()));
  }
  if ((camera.width >> (options_.levels - 1)) < 1 || (camera.height >> (options_.levels - 1)) < 1) {
    throw Error(field("levels") + ": " + std::to_string(options_.levels) + " levels leave no pixel");
  }
  surfels_[0] = map.surfels(0);
  surfels_[1] = map.surfels(1);
  const uint64_t pixels0 = uint64_t(camera.width) * uint64_t(camera.height);
  // Buffer names are unique in a plan: the inactive instance gets its own prefix.
  const std::string name = options_.surfels == PredictedSurfels::kInactive ? "prediction_inactive." : "prediction.";
  params_ = plan.addBuffer(name + "params", sizeof(PredictionParams), gpu::MemoryUse::Upload);
  depth_bits_ = plan.addBuffer(name + "depth_bits", pixels0 * 4, gpu::MemoryUse::DeviceLocal);
  ids_ = plan.addBuffer(name + "ids", pixels0 * 4, gpu::MemoryUse::DeviceLocal);
  int64_splat_ = context.features().int64_atomics;
  if (int64_splat_) splat64_ = plan.addBuffer(name + "splat64", pixels0 * 8, gpu::MemoryUse::DeviceLocal);
  for (int l = 0; l < options_.levels; ++l) {
    cameras_.push_back(camera.atLevel(l));
    const uint64_t n = uint64_t(cameras_.back().width) * uint64_t(cameras_.back().height);
    const std::string prefix = name + "l" + std::to_string(l) + ".";
    levels_.push_back({plan.addBuffer(prefix + "vertices", n * 16, gpu::MemoryUse::DeviceLocal),
                       plan.addBuffer(prefix + "normals", n * 16, gpu::MemoryUse::DeviceLocal),
                       plan.addBuffer(prefix + "intensity", n * 4, gpu::MemoryUse::DeviceLocal)});
  }
}

ModelPrediction::~ModelPrediction() = default;

void ModelPrediction::build(const gpu::MemoryArena& arena) {
  arena_ = &arena;
  kernels_ = std::make_unique<Kernels>();
  Kernels& k = *kernels_;
  const uint32_t wg = options_.image_workgroup_size;
  auto make = [&](const char* name, std::span<const uint32_t> spirv, uint32_t buffers, uint32_t push_bytes,
                  std::array<uint32_t, 3> workgroup, uint32_t sets) {
    gpu::KernelSpec spec;
    spec.name = name;
    spec.spirv = spirv;
    spec.storage_buffers = buffers;
    spec.push_constant_bytes = push_bytes;
    spec.workgroup_size = workgroup;
    spec.max_binding_sets = sets;
    return gpu::ComputeKernel::create(context_, std::move(spec));
  };
  const std::array<uint32_t, 3> surfel_wg = {options_.surfel_workgroup_size, 1, 1};
  if (int64_splat_) {
    k.depth = make("map_predict_splat64", shaders::map_predict_splat64, 4, 0, surfel_wg, 2);
    k.attributes = make("map_predict_attributes64", shaders::map_predict_attributes64, 8, 0, {wg, wg, 1}, 2);
  } else {
    k.depth = make("map_predict_depth", shaders::map_predict_depth, 5, 0, surfel_wg, 2);
    k.id = make("map_predict_id", shaders::map_predict_id, 5, 0, surfel_wg, 2);
    k.attributes = make("map_predict_attributes", shaders::map_predict_attributes, 6, 0, {wg, wg, 1}, 2);
  }
  k.subsample = make("map_pyramid_subsample", shaders::map_pyramid_subsample, 6, sizeof(SubsamplePush), {wg, wg, 1},
                     static_cast<uint32_t>(std::max(1, options_.levels - 1)));

  const uint64_t capacity_groups =
      (uint64_t{map_options_.capacity} + options_.surfel_workgroup_size - 1) / options_.surfel_workgroup_size;
  k.splat_groups = static_cast<uint32_t>(std::min<uint64_t>(options_.surfel_workgroups, capacity_groups));

  auto buffer = [&](gpu::BufferId id) { return &arena.buffer(id); };
  const ModelLevelBuffers& l0 = levels_[0];
  for (int parity = 0; parity < 2; ++parity) {
    const gpu::GpuBuffer* surfels = buffer(surfels_[parity]);
    if (int64_splat_) {
      k.depth_sets[parity] = k.depth->bind({buffer(state_), buffer(params_), surfels, buffer(splat64_)});
      k.attribute_sets[parity] =
          k.attributes->bind({buffer(params_), surfels, buffer(ids_), buffer(l0.vertices), buffer(l0.normals),
                              buffer(l0.intensity), buffer(splat64_), buffer(depth_bits_)});
      continue;
    }
    k.depth_sets[parity] = k.depth->bind({buffer(state_), buffer(params_), surfels, buffer(depth_bits_), buffer(ids_)});
    k.id_sets[parity] = k.id->bind({buffer(state_), buffer(params_), surfels, buffer(depth_bits_), buffer(ids_)});
    k.attribute_sets[parity] = k.attributes->bind(
        {buffer(params_), surfels, buffer(ids_), buffer(l0.vertices), buffer(l0.normals), buffer(l0.intensity)});
  }
  for (int l = 1; l < options_.levels; ++l) {
    const ModelLevelBuffers& level = levels_[l];
    k.subsample_sets.push_back(
        k.subsample->bind({buffer(l0.vertices), buffer(l0.normals), buffer(l0.intensity), buffer(level.vertices),
                           buffer(level.normals), buffer(level.intensity)}));
  }
}

PredictionParams ModelPrediction::makeParams(const SE3d& T_C_W, std::uint32_t frame) const {
  PredictionParams params;
  params.view = MapView::make(T_C_W, cameras_[0], frame);
  params.confidence_threshold = map_options_.confidence_threshold;
  params.time_window_frames = map_options_.time_window_frames;
  params.young_map_frames = options_.young_map_frames;
  params.min_depth_m = options_.min_depth_m;
  params.max_depth_m = map_options_.max_depth_m;
  params.max_half_footprint_px = options_.max_half_footprint_px;
  params.surfels = static_cast<std::uint32_t>(options_.surfels);
  return params;
}

void ModelPrediction::setView(const SE3d& T_C_W, std::uint32_t frame) const {
  const PredictionParams params = makeParams(T_C_W, frame);
  std::memcpy(arena_->buffer(params_).mapped, &params, sizeof(params));
}

void ModelPrediction::setView(const SE3d& T_C_W, std::uint32_t frame, const SurfelSelection& selection) const {
  if ((options_.surfels == PredictedSurfels::kInactive) != (selection.surfels == PredictedSurfels::kInactive)) {
    throw Error("model prediction: only the inactive instance renders the inactive surfels, and only them");
  }
  PredictionParams params = makeParams(T_C_W, frame);
  params.surfels = static_cast<std::uint32_t>(selection.surfels);
  params.created_before = selection.created_before;
  std::memcpy(arena_->buffer(params_).mapped, &params, sizeof(params));
}

void ModelPrediction::record(gpu::CommandRecorder& recorder, int parity) const {
  const Kernels& k = *kernels_;
  const int p = parity & 1;
  if (int64_splat_) {
    recorder.fillBuffer(arena_->buffer(splat64_), 0xffffffffu);  // key 0xffffffff, index kNoSurfel
    recorder.computeBarrier();
    recorder.dispatch(*k.depth, k.depth_sets[p], {k.splat_groups, 1, 1});
    recorder.computeBarrier();
  } else {
    recorder.fillBuffer(arena_->buffer(depth_bits_), 0xffffffffu);  // above every positive float's bits
    recorder.fillBuffer(arena_->buffer(ids_), kNoSurfel);
    recorder.computeBarrier();
    recorder.dispatch(*k.depth, k.depth_sets[p], {k.splat_groups, 1, 1});
    recorder.computeBarrier();
    recorder.dispatch(*k.id, k.id_sets[p], {k.splat_groups, 1, 1});
    recorder.computeBarrier();
  }
  const PinholeCamera& camera0 = cameras_[0];
  recorder.dispatch(
      *k.attributes, k.attribute_sets[p],
      k.attributes->groupsFor(static_cast<uint32_t>(camera0.width), static_cast<uint32_t>(camera0.height)));
  recorder.computeBarrier();
  if (options_.levels > 1) {
    for (int l = 1; l < options_.levels; ++l) {
      const PinholeCamera& camera = cameras_[l];
      const SubsamplePush push{camera0.width, camera.width, camera.height, 1 << l};
      recorder.dispatch(
          *k.subsample, k.subsample_sets[l - 1],
          k.subsample->groupsFor(static_cast<uint32_t>(camera.width), static_cast<uint32_t>(camera.height)), push);
    }
    recorder.computeBarrier();
  }
}

}  // namespace vifusion::map
