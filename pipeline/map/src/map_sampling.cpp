#include "vifusion/map/map_sampling.hpp"

#include <algorithm>
#include <cstring>
#include <string>

#include "vifusion/core/error.hpp"
#include "vifusion/gpu/compute_kernel.hpp"
#include "vifusion/shaders/spirv.hpp"

namespace vifusion::map {
namespace {

/// std430 mirror of map_sample.comp's GatherParams.
struct GatherParams {
  std::uint32_t point_count = 0;
  std::int32_t width = 0;   ///< [px]
  std::int32_t height = 0;  ///< [px]
  std::uint32_t pad = 0;
};
static_assert(sizeof(GatherParams) == 16);

/// Specialization constant id of kMaxNodes in map_sample.comp (0..2 are the workgroup size).
constexpr std::uint32_t kMaxNodesConstantId = 3;
/// Workgroups per dispatch at most: Vulkan's guaranteed maxComputeWorkGroupCount[0]; the kernels are
/// grid-stride, so a larger count is covered by fewer groups.
constexpr std::uint32_t kMaxWorkgroups = 65'535;

std::string field(const char* name) { return std::string("map sampling option '") + name + "'"; }

std::uint32_t workgroupsFor(std::uint32_t entries, std::uint32_t workgroup_size) {
  return std::min(kMaxWorkgroups, (entries + workgroup_size - 1) / workgroup_size);
}

const char* setName(PredictedSurfels surfels) {
  return surfels == PredictedSurfels::kInactive ? "map_gather.inactive." : "map_gather.active.";
}

std::uint32_t frameOf(float frame) { return static_cast<std::uint32_t>(frame); }

}  // namespace

void MapSamplingOptions::validate() const {
  const std::string range = " must be in 1.." + std::to_string(kMaxSamplingEntries);
  if (max_nodes == 0 || max_nodes > kMaxSamplingEntries) throw Error(field("max_nodes") + range);
  if (max_points == 0 || max_points > kMaxSamplingEntries) throw Error(field("max_points") + range);
  if (node_workgroup_size == 0 || node_workgroup_size > 1024) {
    throw Error(field("node_workgroup_size") + " must be in 1..1024");
  }
  if (point_workgroup_size == 0 || point_workgroup_size > 1024) {
    throw Error(field("point_workgroup_size") + " must be in 1..1024");
  }
}

std::uint32_t nodeSampleStride(std::uint32_t surfel_count, std::uint32_t max_nodes) {
  return std::max(1u, surfel_count / max_nodes + (surfel_count % max_nodes != 0u ? 1u : 0u));
}

NodeSampleHeader sampleNodesCpu(std::span<const Surfel> surfels, std::uint32_t max_nodes,
                                std::span<MapNodeSample> out) {
  NodeSampleHeader header;
  header.surfel_count = static_cast<std::uint32_t>(surfels.size());
  header.stride = nodeSampleStride(header.surfel_count, max_nodes);
  header.sample_count = header.surfel_count == 0 ? 0u : (header.surfel_count - 1u) / header.stride + 1u;
  for (std::uint32_t j = 0; j < header.sample_count; ++j) {
    const Surfel& s = surfels[std::size_t{j} * header.stride];
    MapNodeSample& sample = out[j];
    for (int c = 0; c < 3; ++c) sample.p_W[c] = s.position_confidence[c];
    sample.created_frame = frameOf(s.colour_times.y());
  }
  return header;
}

void gatherPointsCpu(std::span<const Surfel> surfels, ImageView<const std::uint32_t> ids,
                     std::span<const GatherPixel> pixels, std::span<GatheredPoint> out) {
  for (std::size_t j = 0; j < pixels.size(); ++j) {
    const GatherPixel pixel = pixels[j];
    const bool inside = pixel.x >= 0 && pixel.y >= 0 && pixel.x < ids.width && pixel.y < ids.height;
    const std::uint32_t id = inside ? ids(pixel.x, pixel.y) : kNoSurfel;
    GatheredPoint& point = out[j];
    point = GatheredPoint{};
    if (id == kNoSurfel || id >= surfels.size()) continue;
    const Surfel& s = surfels[id];
    for (int c = 0; c < 3; ++c) {
      point.p_W[c] = s.position_confidence[c];
      point.n_W[c] = s.normal_radius[c];
    }
    point.created_frame = frameOf(s.colour_times.y());
    point.updated_frame = frameOf(s.colour_times.z());
    point.surfel = id;
    point.valid = 1;
  }
}

std::size_t toLoopNodeSamples(std::span<const MapNodeSample> samples, std::span<loop::NodeSample> out) {
  if (out.size() < samples.size()) {
    throw Error("map sampling: " + std::to_string(samples.size()) + " node samples do not fit into " +
                std::to_string(out.size()));
  }
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const MapNodeSample& sample = samples[i];
    out[i].p_W = Eigen::Vector3d(sample.p_W[0], sample.p_W[1], sample.p_W[2]);
    out[i].time = sample.created_frame;
  }
  return samples.size();
}

// ---- MapSampling -------------------------------------------------------------------------------------------

struct MapSampling::Kernels {
  std::unique_ptr<gpu::ComputeKernel> nodes;
  gpu::BindingSet sets[2];
  std::unique_ptr<gpu::CommandSequence> sequences[2];  ///< per surfel-array parity
  std::uint32_t groups = 0;
};

MapSampling::MapSampling(gpu::GpuContext& context, gpu::CapacityPlan& plan, const MapBuffers& map,
                         const MapSamplingOptions& options)
    : context_(context), map_(map), options_(options) {
  options_.validate();
  samples_ = plan.addBuffer("map_sample.nodes", std::uint64_t{options_.max_nodes} * sizeof(MapNodeSample),
                            gpu::MemoryUse::Readback);
  header_ = plan.addBuffer("map_sample.header", sizeof(NodeSampleHeader), gpu::MemoryUse::Readback);
}

MapSampling::~MapSampling() = default;

void MapSampling::build(const gpu::MemoryArena& arena) {
  arena_ = &arena;
  kernels_ = std::make_unique<Kernels>();
  Kernels& k = *kernels_;
  gpu::KernelSpec spec;
  spec.name = "map_sample_nodes";
  spec.spirv = shaders::map_sample_nodes;
  spec.storage_buffers = 4;
  spec.workgroup_size = {options_.node_workgroup_size, 1, 1};
  spec.constants = {{kMaxNodesConstantId, options_.max_nodes}};
  spec.max_binding_sets = 2;
  k.nodes = gpu::ComputeKernel::create(context_, std::move(spec));
  k.groups = workgroupsFor(options_.max_nodes, options_.node_workgroup_size);
  const auto buffer = [&](gpu::BufferId id) { return &arena.buffer(id); };
  for (int parity = 0; parity < 2; ++parity) {
    k.sets[parity] =
        k.nodes->bind({buffer(map_.state()), buffer(map_.surfels(parity)), buffer(samples_), buffer(header_)});
    k.sequences[parity] = gpu::CommandSequence::create(context_, "map sample nodes " + std::to_string(parity));
    k.sequences[parity]->record([&](gpu::CommandRecorder& recorder) {
      recorder.computeBarrier();  // after earlier submissions' map writes
      record(recorder, parity);
    });
  }
}

void MapSampling::record(gpu::CommandRecorder& recorder, int parity) const {
  recorder.dispatch(*kernels_->nodes, kernels_->sets[parity & 1], {kernels_->groups, 1, 1});
  recorder.hostReadBarrier();
}

void MapSampling::sample() { kernels_->sequences[map_.current()]->run(); }

NodeSampleHeader MapSampling::header() const {
  NodeSampleHeader header;
  std::memcpy(&header, arena_->buffer(header_).mapped, sizeof(header));
  return header;
}

std::span<const MapNodeSample> MapSampling::samples() const {
  const std::uint32_t n = std::min(header().sample_count, options_.max_nodes);
  return arena_->buffer(samples_).hostSpan<const MapNodeSample>().first(n);
}

std::size_t MapSampling::readNodeSamples(std::span<loop::NodeSample> out) const {
  return toLoopNodeSamples(samples(), out);
}

// ---- PredictionGather --------------------------------------------------------------------------------------

struct PredictionGather::Kernels {
  std::unique_ptr<gpu::ComputeKernel> gather;
  gpu::BindingSet sets[2];
  std::unique_ptr<gpu::CommandSequence> sequences[2];  ///< per surfel-array parity
  std::uint32_t groups = 0;
};

PredictionGather::PredictionGather(gpu::GpuContext& context, gpu::CapacityPlan& plan, const MapBuffers& map,
                                   const ModelPrediction& prediction, const MapSamplingOptions& options)
    : context_(context),
      map_(map),
      options_(options),
      ids_(prediction.splatIds()),
      width_(prediction.camera(0).width),
      height_(prediction.camera(0).height) {
  options_.validate();
  const std::string name = setName(prediction.surfels());
  params_ = plan.addBuffer(name + "params", sizeof(GatherParams), gpu::MemoryUse::Upload);
  pixels_ =
      plan.addBuffer(name + "pixels", std::uint64_t{options_.max_points} * sizeof(GatherPixel), gpu::MemoryUse::Upload);
  points_ = plan.addBuffer(name + "points", std::uint64_t{options_.max_points} * sizeof(GatheredPoint),
                           gpu::MemoryUse::Readback);
}

PredictionGather::~PredictionGather() = default;

void PredictionGather::build(const gpu::MemoryArena& arena) {
  arena_ = &arena;
  kernels_ = std::make_unique<Kernels>();
  Kernels& k = *kernels_;
  gpu::KernelSpec spec;
  spec.name = "map_gather_points";
  spec.spirv = shaders::map_gather_points;
  spec.storage_buffers = 6;
  spec.workgroup_size = {options_.point_workgroup_size, 1, 1};
  spec.max_binding_sets = 2;
  k.gather = gpu::ComputeKernel::create(context_, std::move(spec));
  k.groups = workgroupsFor(options_.max_points, options_.point_workgroup_size);
  const auto buffer = [&](gpu::BufferId id) { return &arena.buffer(id); };
  for (int parity = 0; parity < 2; ++parity) {
    k.sets[parity] = k.gather->bind({buffer(map_.state()), buffer(map_.surfels(parity)), buffer(points_),
                                     buffer(params_), buffer(pixels_), buffer(ids_)});
    k.sequences[parity] = gpu::CommandSequence::create(context_, "map gather " + std::to_string(parity));
    k.sequences[parity]->record([&](gpu::CommandRecorder& recorder) {
      recorder.computeBarrier();  // after earlier submissions' prediction and map writes
      record(recorder, parity);
    });
  }
  setPixels({});  // a gather before any setPixels() reads nothing
}

void PredictionGather::setPixels(std::span<const GatherPixel> pixels) {
  if (pixels.size() > options_.max_points) {
    throw Error("map gather: " + std::to_string(pixels.size()) + " pixels, at most " +
                std::to_string(options_.max_points) + " (max_points)");
  }
  if (!pixels.empty()) std::memcpy(arena_->buffer(pixels_).mapped, pixels.data(), pixels.size_bytes());
  point_count_ = static_cast<std::uint32_t>(pixels.size());
  const GatherParams params{point_count_, width_, height_, 0};
  std::memcpy(arena_->buffer(params_).mapped, &params, sizeof(params));
}

void PredictionGather::record(gpu::CommandRecorder& recorder, int parity) const {
  recorder.dispatch(*kernels_->gather, kernels_->sets[parity & 1], {kernels_->groups, 1, 1});
  recorder.hostReadBarrier();
}

void PredictionGather::gather() { kernels_->sequences[map_.current()]->run(); }

std::span<const GatheredPoint> PredictionGather::points() const {
  return arena_->buffer(points_).hostSpan<const GatheredPoint>().first(point_count_);
}

}  // namespace vifusion::map
