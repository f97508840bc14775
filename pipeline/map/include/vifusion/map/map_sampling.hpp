#pragma once
// What loop closure reads out of the surfel map on the GPU (shaders/map_sample.comp), with its CPU references:
//
//  MapSampling      deformation-graph node samples: every stride-th live surfel of the current array,
//                   stride = max(1, ⌈surfel_count / max_nodes⌉) computed on the GPU from the map state's count, as
//                   (p_W [m], creation frame), at most max_nodes of them, plus how many were written.
//                   The array is not in creation order (map_buffers.hpp: the inactive prefix, then the active
//                   range, each grown in order), so neither are the samples: loop::DeformationGraph::build sorts
//                   them by creation frame.
//  PredictionGather loop-closure constraint points: for up to max_points level-0 pixels written by the host, the
//                   surfel that won each pixel in ONE ModelPrediction (its splat id image, bound at
//                   construction): centre and normal in W, creation and last-update frames, or valid = 0 where
//                   no surfel won. One gather per prediction: Slam's active and inactive predictions each get
//                   their own, with their own buffers ("map_gather.active.*", "map_gather.inactive.*").
//
// Which surfel array the gather reads: the ids index the array the prediction RENDERED. In Slam's frame
// (Slam::recordMapUpdate) fusion reads array `parity`, compaction writes the survivors to `parity ^ 1`, the
// predictions render `parity ^ 1`, and Slam then flips, so after the frame the rendered array is
// MapBuffers::current() (a frame that is not fused renders `parity` and does not flip: current() again). Hence
// gather() reads current(); recorded into Slam's own sequence, after the predictions, it must read the array they
// rendered: record(recorder, parity ^ 1) in the fused sequence, record(recorder, parity) in the predict-only one.
// The map must not be fused or compacted between the prediction and the gather (the ids would name other
// surfels); the shader only guards against ids ≥ surfel_count.
//
// Memory: everything from the capacity plan (outputs Readback, host-written inputs Upload), sequences recorded
// once per surfel-array parity in build(); nothing allocates afterwards. sample()/gather() are one blocking
// submission each: call them from the thread that owns the GPU with no submission in flight that writes the
// map.

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <span>

#include "vifusion/core/image.hpp"
#include "vifusion/gpu/capacity_plan.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/gpu/gpu_context.hpp"
#include "vifusion/gpu/memory_arena.hpp"
#include "vifusion/loop/deformation_graph.hpp"
#include "vifusion/map/map_buffers.hpp"
#include "vifusion/map/model_prediction.hpp"
#include "vifusion/map/surfel.hpp"

namespace vifusion::map {

/// Upper bound of max_nodes and max_points: the loop graph's own node bound, and it keeps the buffers small.
inline constexpr std::uint32_t kMaxSamplingEntries = 1'000'000;

struct MapSamplingOptions {
  /// Node samples at most: the deformation graph's capacity (loop::DeformationGraphOptions::max_nodes,
  /// ElasticFusion's 1024). In [1, kMaxSamplingEntries].
  std::uint32_t max_nodes = 1024;
  /// Pixels one gather reads at most (ElasticFusion's local closure: a 32 × 24 grid, 768). In
  /// [1, kMaxSamplingEntries].
  std::uint32_t max_points = 1024;
  std::uint32_t node_workgroup_size = 64;   ///< invocations per workgroup of map_sample_nodes, 1..1024
  std::uint32_t point_workgroup_size = 64;  ///< invocations per workgroup of map_gather_points, 1..1024

  /// Throws vifusion::Error naming the field that is out of range.
  void validate() const;
};

/// std430 mirror of NodeSample in map_sample.comp (16 bytes).
struct MapNodeSample {
  float p_W[3] = {};                ///< surfel position in W [m]
  std::uint32_t created_frame = 0;  ///< uint(colour_times.y)
};
static_assert(sizeof(MapNodeSample) == 16, "must match the std430 layout in shaders/map_sample.comp");

/// std430 mirror of map_sample.comp's node header (16 bytes).
struct NodeSampleHeader {
  std::uint32_t sample_count = 0;  ///< samples written, ≤ max_nodes
  std::uint32_t stride = 0;        ///< surfels between samples, ≥ 1
  std::uint32_t surfel_count = 0;  ///< the live count they were taken from
  std::uint32_t pad = 0;

  bool operator==(const NodeSampleHeader&) const = default;
};
static_assert(sizeof(NodeSampleHeader) == 16);

/// A level-0 pixel to gather at [px] (ivec2 in map_sample.comp).
struct GatherPixel {
  std::int32_t x = 0;
  std::int32_t y = 0;
};
static_assert(sizeof(GatherPixel) == 8);

/// std430 mirror of GatheredPoint in map_sample.comp (48 bytes).
struct GatheredPoint {
  float p_W[3] = {};                 ///< surfel centre in W [m]
  std::uint32_t created_frame = 0;   ///< uint(colour_times.y)
  float n_W[3] = {};                 ///< surfel normal in W, as stored
  std::uint32_t updated_frame = 0;   ///< uint(colour_times.z)
  std::uint32_t surfel = kNoSurfel;  ///< index in the rendered array, kNoSurfel when invalid
  std::uint32_t valid = 0;           ///< 1: a surfel won the pixel; 0: none (other fields zero)
  std::uint32_t pad[2] = {};

  Eigen::Vector3f position() const { return {p_W[0], p_W[1], p_W[2]}; }
  Eigen::Vector3f normal() const { return {n_W[0], n_W[1], n_W[2]}; }
};
static_assert(sizeof(GatheredPoint) == 48, "must match the std430 layout in shaders/map_sample.comp");

/// stride = max(1, ⌈surfel_count / max_nodes⌉) (max_nodes ≥ 1).
std::uint32_t nodeSampleStride(std::uint32_t surfel_count, std::uint32_t max_nodes);

/// CPU reference of map_sample_nodes: samples every stride-th of the live `surfels` (all of them are live,
/// surfel_count = size) into out[0, n) and returns the header. `out` has ≥ n = ⌈surfel_count / stride⌉ ≤
/// max_nodes entries; entries from n on are left as they were.
NodeSampleHeader sampleNodesCpu(std::span<const Surfel> surfels, std::uint32_t max_nodes, std::span<MapNodeSample> out);

/// CPU reference of map_gather_points: for each pixel, the surfel `ids` (a prediction's level-0 splat id image)
/// names there, from the live `surfels` of the array that prediction rendered. `out` has ≥ pixels.size() entries.
void gatherPointsCpu(std::span<const Surfel> surfels, ImageView<const std::uint32_t> ids,
                     std::span<const GatherPixel> pixels, std::span<GatheredPoint> out);

/// Converts node samples to the deformation graph's input into the caller's `out` (no allocation) and returns
/// samples.size(). Throws vifusion::Error when `out` is shorter.
std::size_t toLoopNodeSamples(std::span<const MapNodeSample> samples, std::span<loop::NodeSample> out);

class MapSampling {
 public:
  /// Declares the sample and header buffers (Readback). `map` must outlive this object. Throws vifusion::Error on
  /// bad options.
  MapSampling(gpu::GpuContext& context, gpu::CapacityPlan& plan, const MapBuffers& map,
              const MapSamplingOptions& options = {});
  ~MapSampling();
  MapSampling(const MapSampling&) = delete;
  MapSampling& operator=(const MapSampling&) = delete;

  /// Creates the kernel, one binding set and one recorded sequence per surfel-array parity.
  void build(const gpu::MemoryArena& arena);

  /// Records the sampling of array `parity` for callers that put it into their own sequence (after a barrier
  /// that orders it behind the map writes it reads), ending with a barrier that makes the samples host-visible.
  void record(gpu::CommandRecorder& recorder, int parity) const;
  /// Samples the current array (MapBuffers::current()) and waits for it.
  void sample();

  /// What the last sampling wrote (valid once its submission completed).
  NodeSampleHeader header() const;
  /// The samples [0, header().sample_count), in creation order; a view into the readback buffer, valid until the
  /// next sampling.
  std::span<const MapNodeSample> samples() const;
  /// samples() converted into the caller's `out` (≥ max_nodes entries always suffice); returns how many.
  std::size_t readNodeSamples(std::span<loop::NodeSample> out) const;

  gpu::BufferId samplesBuffer() const { return samples_; }
  gpu::BufferId headerBuffer() const { return header_; }

 private:
  struct Kernels;

  gpu::GpuContext& context_;
  const MapBuffers& map_;
  MapSamplingOptions options_;
  gpu::BufferId samples_;
  gpu::BufferId header_;
  const gpu::MemoryArena* arena_ = nullptr;
  std::unique_ptr<Kernels> kernels_;
};

class PredictionGather {
 public:
  /// Declares the pixel and parameter buffers (Upload) and the point buffer (Readback), named after the
  /// prediction's surfel set; reads `prediction`'s splat ids (level 0). `map` and `prediction` must outlive
  /// this object. Throws vifusion::Error on bad options.
  PredictionGather(gpu::GpuContext& context, gpu::CapacityPlan& plan, const MapBuffers& map,
                   const ModelPrediction& prediction, const MapSamplingOptions& options = {});
  ~PredictionGather();
  PredictionGather(const PredictionGather&) = delete;
  PredictionGather& operator=(const PredictionGather&) = delete;

  /// Creates the kernel, one binding set and one recorded sequence per surfel-array parity.
  void build(const gpu::MemoryArena& arena);

  /// Writes the pixels for the next gather (host, no allocation). Throws vifusion::Error when there are more
  /// than max_points.
  void setPixels(std::span<const GatherPixel> pixels);
  /// Records the gather from array `parity` — the one the prediction rendered — for callers that put it into
  /// their own sequence (after the prediction's record(), which ends with a compute barrier), ending with a
  /// barrier that makes the points host-visible.
  void record(gpu::CommandRecorder& recorder, int parity) const;
  /// Gathers from the current array (MapBuffers::current(), the rendered one after Slam's frame) and waits.
  void gather();

  /// The points [0, pixels set), one per pixel in order (valid once the gather completed); a view into the
  /// readback buffer, valid until the next gather.
  std::span<const GatheredPoint> points() const;

  gpu::BufferId pointsBuffer() const { return points_; }
  std::uint32_t maxPoints() const { return options_.max_points; }

 private:
  struct Kernels;

  gpu::GpuContext& context_;
  const MapBuffers& map_;
  MapSamplingOptions options_;
  gpu::BufferId ids_;
  int width_ = 0;
  int height_ = 0;
  std::uint32_t point_count_ = 0;
  gpu::BufferId params_;
  gpu::BufferId pixels_;
  gpu::BufferId points_;
  const gpu::MemoryArena* arena_ = nullptr;
  std::unique_ptr<Kernels> kernels_;
};

}  // namespace vifusion::map
