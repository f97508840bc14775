#include "vifusion/map/surfel_fusion.hpp"

#include <algorithm>
#include <cstring>
#include <string>

#include "grid_stride.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/shaders/spirv.hpp"

namespace vifusion::map {
namespace {

/// Invocations per workgroup of every fusion kernel (1-D). map_insert's shared-memory scan is
/// sized by it.
constexpr std::uint32_t kWorkgroupSize = 256;
/// Surfel kernels loop grid-stride, so a few workgroups cover any count; this many keep every
/// GPU busy without launching capacity/256 mostly idle workgroups when the map is small (CPU
/// devices: grid_stride.hpp).
constexpr std::uint32_t kMaxSurfelWorkgroups = 1024;

/// Pixels per run of map_associate and map_insert (fusion_params.glsl: pixelRun), one invocation
/// per run. On CPU devices long runs (the sliding window of the association reads 2 extra columns
/// per run); GPUs want more invocations and shorter runs.
std::uint32_t runPixels(const gpu::GpuContext& context) {
  return context.features().device_type == VK_PHYSICAL_DEVICE_TYPE_CPU ? 32u : 8u;
}

std::uint32_t runCount(const PinholeCamera& camera, std::uint32_t run_pixels) {
  return static_cast<std::uint32_t>(camera.height) *
         ((static_cast<std::uint32_t>(camera.width) + run_pixels - 1) / run_pixels);
}

struct PassPush {
  std::uint32_t pass = 0;
};

std::uint32_t groupsFor(std::uint64_t items) {
  return static_cast<std::uint32_t>((items + kWorkgroupSize - 1) / kWorkgroupSize);
}

}  // namespace

FusionInputs FusionInputs::fromPreprocess(const preprocess::PreprocessStage& stage) {
  return {stage.level(0).vertices, stage.level(0).normals, stage.rgbWords()};
}

const char* fusionStepName(FusionStep step) {
  switch (step) {
    case FusionStep::Index:
      return "index";
    case FusionStep::Associate:
      return "associate";
    case FusionStep::Fuse:
      return "fuse";
    case FusionStep::Insert:
      return "insert";
  }
  return "?";
}

/// One kernel per shader, each with one binding set per surfel-array parity.
struct SurfelFusion::Kernels {
  std::unique_ptr<gpu::ComputeKernel> index, associate, fuse, insert;
  gpu::BindingSet index_sets[2], associate_sets[2], fuse_sets[2], insert_sets[2];
};

SurfelFusion::SurfelFusion(gpu::GpuContext& context, gpu::CapacityPlan& plan, const MapBuffers& map,
                           const PinholeCamera& camera, const FusionOptions& options)
    : context_(context), map_(map), camera_(camera), options_(options) {
  options_.validate();
  if (camera.width != map.width() || camera.height != map.height()) {
    throw Error("surfel fusion: camera of " + std::to_string(camera.width) + "x" + std::to_string(camera.height) +
                " but the map's index map is " + std::to_string(map.width()) + "x" + std::to_string(map.height()));
  }
  const std::uint64_t pixels = std::uint64_t(camera.width) * std::uint64_t(camera.height);
  params_buffer_ = plan.addBuffer("map.fusion_params", sizeof(FusionParams), gpu::MemoryUse::Upload);
  pixel_match_ = plan.addBuffer("map.pixel_match", pixels * sizeof(std::uint32_t), gpu::MemoryUse::DeviceLocal);
  surfel_claim_ = plan.addBuffer("map.surfel_claim", std::uint64_t{map.capacity()} * sizeof(std::uint32_t),
                                 gpu::MemoryUse::DeviceLocal);
  run_pixels_ = runPixels(context);
  run_counts_ = plan.addBuffer("map.run_counts", std::uint64_t{runCount(camera, run_pixels_)} * sizeof(std::uint32_t),
                               gpu::MemoryUse::DeviceLocal);
}

SurfelFusion::~SurfelFusion() = default;

void SurfelFusion::build(const gpu::MemoryArena& arena, const FusionInputs& inputs) {
  arena_ = &arena;
  kernels_ = std::make_unique<Kernels>();
  Kernels& k = *kernels_;
  auto make = [&](const char* name, std::span<const std::uint32_t> spirv, std::uint32_t buffers,
                  std::uint32_t push_bytes) {
    gpu::KernelSpec spec;
    spec.name = name;
    spec.spirv = spirv;
    spec.storage_buffers = buffers;
    spec.push_constant_bytes = push_bytes;
    spec.workgroup_size = {kWorkgroupSize, 1, 1};
    spec.constants = {{3, run_pixels_}};  // kRunPixels (read by map_associate and map_insert)
    spec.max_binding_sets = 2;
    return gpu::ComputeKernel::create(context_, std::move(spec));
  };
  k.index = make("map_index", shaders::map_index, 5, sizeof(PassPush));
  k.associate = make("map_associate", shaders::map_associate, 8, 0);
  k.fuse = make("map_fuse", shaders::map_fuse, 7, 0);
  k.insert = make("map_insert", shaders::map_insert, 8, sizeof(PassPush));

  auto buffer = [&](gpu::BufferId id) { return &arena.buffer(id); };
  for (int parity = 0; parity < 2; ++parity) {
    const gpu::GpuBuffer* surfels = buffer(map_.surfels(parity));
    k.index_sets[parity] = k.index->bind(
        {surfels, buffer(map_.state()), buffer(params_buffer_), buffer(map_.indexDepth()), buffer(map_.indexId())});
    k.associate_sets[parity] =
        k.associate->bind({buffer(inputs.vertices), buffer(inputs.normals), surfels, buffer(map_.indexId()),
                           buffer(params_buffer_), buffer(pixel_match_), buffer(surfel_claim_), buffer(run_counts_)});
    k.fuse_sets[parity] = k.fuse->bind({buffer(inputs.vertices), buffer(inputs.normals), buffer(inputs.rgb_words),
                                        buffer(params_buffer_), buffer(map_.state()), buffer(surfel_claim_), surfels});
    k.insert_sets[parity] = k.insert->bind({buffer(inputs.vertices), buffer(inputs.normals), buffer(inputs.rgb_words),
                                            buffer(params_buffer_), buffer(pixel_match_), buffer(run_counts_),
                                            buffer(map_.state()), surfels});
  }
}

void SurfelFusion::setFrame(const SE3d& T_W_C, std::uint32_t frame, const FusionPoseUncertainty& uncertainty) {
  params_ = FusionParams::make(T_W_C, frame, camera_, map_.options(), options_, uncertainty);
  std::memcpy(arena_->buffer(params_buffer_).mapped, &params_, sizeof(params_));
}

void SurfelFusion::record(gpu::CommandRecorder& recorder, int parity) const {
  for (FusionStep step : kAllFusionSteps) recordStep(recorder, step, parity);
}

void SurfelFusion::recordStep(gpu::CommandRecorder& recorder, FusionStep step, int parity) const {
  const Kernels& k = *kernels_;
  const int p = parity & 1;
  const std::uint32_t surfel_groups =
      surfelWorkgroups(context_, std::min(groupsFor(map_.capacity()), kMaxSurfelWorkgroups));
  const std::uint32_t run_groups = groupsFor(runCount(camera_, run_pixels_));
  auto buffer = [&](gpu::BufferId id) -> const gpu::GpuBuffer& { return arena_->buffer(id); };
  switch (step) {
    case FusionStep::Index:
      recorder.fillBuffer(buffer(map_.indexDepth()), 0xFFFFFFFFu);
      recorder.fillBuffer(buffer(map_.indexId()), 0u);
      recorder.fillBuffer(buffer(surfel_claim_), kUnclaimed);
      recorder.computeBarrier();
      // Pass 1 compares against the final depths of pass 0, hence the barrier between them.
      recorder.dispatch(*k.index, k.index_sets[p], {surfel_groups, 1, 1}, PassPush{0});
      recorder.computeBarrier();
      recorder.dispatch(*k.index, k.index_sets[p], {surfel_groups, 1, 1}, PassPush{1});
      break;
    case FusionStep::Associate:
      recorder.dispatch(*k.associate, k.associate_sets[p], {run_groups, 1, 1});
      break;
    case FusionStep::Fuse:
      recorder.dispatch(*k.fuse, k.fuse_sets[p], {surfel_groups, 1, 1});
      break;
    case FusionStep::Insert:
      // The scan turns association's run counts into offsets, which the write pass consumes.
      recorder.dispatch(*k.insert, k.insert_sets[p], {1, 1, 1}, PassPush{0});
      recorder.computeBarrier();
      recorder.dispatch(*k.insert, k.insert_sets[p], {run_groups, 1, 1}, PassPush{1});
      break;
  }
  recorder.computeBarrier();
}

}  // namespace vifusion::map
