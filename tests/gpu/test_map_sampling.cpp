// Loop closure's reads of the surfel map on the GPU (map_sample.comp) against their CPU references, bit for bit
// (both are copies): the deformation graph's node samples from either surfel array, at every stride regime, for a
// map grown the way map_insert and compaction grow it (not in creation order: the graph sorts them); and the
// constraint-point gather at host-chosen pixels of an active and an inactive prediction, reading the array the
// predictions rendered. Also the conversion to loop::NodeSample, the capacity checks and the options' validation.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "block_wall.hpp"
#include "counting_vulkan.hpp"
#include "gpu_test_environment.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/loop/deformation_graph.hpp"
#include "vifusion/map/maintenance_cpu.hpp"
#include "vifusion/map/map_buffers.hpp"
#include "vifusion/map/map_sampling.hpp"
#include "vifusion/map/model_prediction.hpp"
#include "vifusion/test/counting_allocations.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion {
namespace {

using map::GatheredPoint;
using map::GatherPixel;
using map::MapNodeSample;
using map::Surfel;

const PinholeCamera& kCamera = test::kBlockWallCamera;
constexpr std::uint32_t kFrame = test::kBlockWallFrame;  ///< the frame the gather's map is predicted in
constexpr float kStableConfidence = test::kBlockWallStableConfidence;

map::MapOptions mapOptions(std::uint32_t capacity) {
  map::MapOptions options;
  options.capacity = capacity;
  return options;
}

map::PredictionOptions predictionOptions(map::PredictedSurfels surfels) {
  map::PredictionOptions options;
  options.surfels = surfels;
  return options;
}

/// Small workgroups and few nodes, so the grids span several workgroups and every stride regime is reached.
map::MapSamplingOptions smallOptions() {
  map::MapSamplingOptions options;
  options.max_nodes = 100;
  options.max_points = 600;
  options.node_workgroup_size = 32;
  options.point_workgroup_size = 32;
  return options;
}

bool sameBits(const auto& a, const auto& b) { return std::memcmp(&a, &b, sizeof(a)) == 0; }

template <typename T>
std::size_t countDifferent(std::span<const T> a, std::span<const T> b) {
  std::size_t different = a.size() == b.size() ? 0 : std::max(a.size(), b.size());
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) different += sameBits(a[i], b[i]) ? 0 : 1;
  return different;
}

/// A map grown as the GPU grows it, frame by frame: fusion refreshes some active surfels (update frame and
/// confidence; never the creation frame), map_insert appends the frame's new surfels behind the live ones, and
/// compaction removes some (unstable ones that went unseen, a few others) and retires those unseen for longer
/// than kWindowFrames to the inactive prefix, by a stable partition. So the array is not in creation order.
std::vector<Surfel> grownMap(std::uint32_t frames, std::uint32_t seed) {
  constexpr float kWindowFrames = 30.0f;
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::uniform_int_distribution<std::uint32_t> new_surfels(0, 600);
  std::vector<Surfel> live, compacted;
  std::vector<std::uint32_t> keep, retire;
  std::uint32_t active_begin = 0;
  for (std::uint32_t frame = 1; frame <= frames; ++frame) {
    for (std::size_t i = active_begin; i < live.size(); ++i) {
      Surfel& s = live[i];
      if (unit(random) < 0.3f) {
        s.colour_times.z() = static_cast<float>(frame);
        s.position_confidence.w() += 1.0f;
      }
    }
    for (std::uint32_t n = new_surfels(random); n > 0; --n) {
      Surfel s;
      s.position_confidence << 4.0f * unit(random) - 2.0f, 3.0f * unit(random), 4.0f * unit(random), 1.0f;
      s.normal_radius << 0.0f, 0.0f, -1.0f, 0.005f + 0.01f * unit(random);
      s.setPackedColour(random() & 0xffffffu);
      s.colour_times.y() = s.colour_times.z() = static_cast<float>(frame);
      live.push_back(s);
    }
    keep.assign(live.size() - active_begin, 0u);
    retire.assign(live.size() - active_begin, 0u);
    for (std::size_t i = active_begin; i < live.size(); ++i) {
      const Surfel& s = live[i];
      const bool stale_unstable = s.position_confidence.w() < 10.0f && frame - s.colour_times.z() > 20.0f;
      const bool inactive = frame - s.colour_times.z() > kWindowFrames;
      retire[i - active_begin] = inactive ? 1u : 0u;  // map_cleanup's order: inactive first
      keep[i - active_begin] = inactive || stale_unstable || unit(random) < 0.01f ? 0u : 1u;
    }
    compacted.resize(live.size());
    const map::MapExtent extent = map::compactCpu(live, active_begin, keep, retire, compacted);
    compacted.resize(extent.surfel_count);
    active_begin = extent.active_begin;
    std::swap(live, compacted);
  }
  return live;
}

/// A map with an active and an inactive prediction, node sampling and a gather per prediction on one arena,
/// plus uploads into either surfel array and readbacks of both predictions' splat ids.
class SamplingRig {
 public:
  SamplingRig(gpu::GpuContext& context, std::uint32_t capacity, const map::MapSamplingOptions& options)
      : map_(plan_, mapOptions(capacity), kCamera),
        active_(context, plan_, map_, kCamera, predictionOptions(map::PredictedSurfels::kActive)),
        inactive_(context, plan_, map_, kCamera, predictionOptions(map::PredictedSurfels::kInactive)),
        sampling_(context, plan_, map_, options),
        active_gather_(context, plan_, map_, active_, options),
        inactive_gather_(context, plan_, map_, inactive_, options) {
    const std::uint64_t surfel_bytes = std::uint64_t{capacity} * sizeof(Surfel);
    const std::uint64_t id_bytes = std::uint64_t(kCamera.width) * std::uint64_t(kCamera.height) * 4;
    upload_ = plan_.addBuffer("test.surfels", surfel_bytes, gpu::MemoryUse::Upload);
    active_ids_ = plan_.addBuffer("test.active_ids", id_bytes, gpu::MemoryUse::Readback);
    inactive_ids_ = plan_.addBuffer("test.inactive_ids", id_bytes, gpu::MemoryUse::Readback);
    arena_ = gpu::MemoryArena::create(context, plan_);
    active_.build(*arena_);
    inactive_.build(*arena_);
    sampling_.build(*arena_);
    active_gather_.build(*arena_);
    inactive_gather_.build(*arena_);
    map_.reset(*arena_);
    for (int parity = 0; parity < 2; ++parity) {
      uploads_[parity] = gpu::CommandSequence::create(context, "upload " + std::to_string(parity));
      uploads_[parity]->record([&](gpu::CommandRecorder& r) {
        r.copyBuffer(buffer(upload_), buffer(map_.surfels(parity)), surfel_bytes);
        r.computeBarrier();
      });
      predictions_[parity] = gpu::CommandSequence::create(context, "predict " + std::to_string(parity));
      predictions_[parity]->record([&](gpu::CommandRecorder& r) {
        active_.record(r, parity);
        inactive_.record(r, parity);
        r.copyBuffer(buffer(active_.splatIds()), buffer(active_ids_), id_bytes);
        r.copyBuffer(buffer(inactive_.splatIds()), buffer(inactive_ids_), id_bytes);
        r.hostReadBarrier();
      });
    }
  }

  /// Fills surfel array `parity` from the front with `surfels`.
  void writeArray(int parity, std::span<const Surfel> surfels) {
    std::memcpy(buffer(upload_).mapped, surfels.data(), surfels.size_bytes());
    uploads_[parity]->run();
  }
  /// Makes array `parity` the current one, holding `count` live surfels of which [0, active_begin) are the
  /// inactive prefix, in frame `frame`.
  void setMap(int parity, std::uint32_t count, std::uint32_t frame = kFrame, std::uint32_t active_begin = 0) {
    if (map_.current() != parity) map_.flip();
    map::MapState state;
    state.surfel_count = count;
    state.frame = frame;
    state.active_begin = active_begin;
    std::memcpy(buffer(map_.state()).mapped, &state, sizeof(state));
  }
  /// Both predictions of the current array, camera at the origin of W looking along +z.
  void predict() {
    active_.setView(SE3d(), kFrame);
    inactive_.setView(SE3d(), kFrame);
    predictions_[map_.current()]->run();
  }
  ImageView<const std::uint32_t> ids(map::PredictedSurfels set) const {
    const gpu::BufferId id = set == map::PredictedSurfels::kActive ? active_ids_ : inactive_ids_;
    return {buffer(id).hostSpan<const std::uint32_t>().data(), kCamera.width, kCamera.height};
  }

  map::MapSampling& sampling() { return sampling_; }
  map::PredictionGather& gather(map::PredictedSurfels set) {
    return set == map::PredictedSurfels::kActive ? active_gather_ : inactive_gather_;
  }
  const map::ModelPrediction& prediction(map::PredictedSurfels set) const {
    return set == map::PredictedSurfels::kActive ? active_ : inactive_;
  }
  const gpu::CapacityPlan& plan() const { return plan_; }

 private:
  const gpu::GpuBuffer& buffer(gpu::BufferId id) const { return arena_->buffer(id); }

  gpu::CapacityPlan plan_;
  map::MapBuffers map_;
  map::ModelPrediction active_;
  map::ModelPrediction inactive_;
  map::MapSampling sampling_;
  map::PredictionGather active_gather_;
  map::PredictionGather inactive_gather_;
  gpu::BufferId upload_, active_ids_, inactive_ids_;
  std::unique_ptr<gpu::MemoryArena> arena_;
  std::unique_ptr<gpu::CommandSequence> uploads_[2], predictions_[2];
};

class MapSamplingTest : public test::GpuTest {};

TEST_F(MapSamplingTest, NodeSamplesMatchTheCpuReferenceFromEitherArray) {
  const std::vector<Surfel> grown = grownMap(120, 11);
  ASSERT_GT(grown.size(), 20'000u);
  const auto capacity = static_cast<std::uint32_t>(grown.size());
  const map::MapSamplingOptions options = smallOptions();
  SamplingRig rig(context(), capacity, options);
  // Array 1 holds the map reversed, so reading the wrong array shows.
  std::vector<Surfel> reversed(grown.rbegin(), grown.rend());
  rig.writeArray(0, grown);
  rig.writeArray(1, reversed);

  struct Case {
    int parity;
    std::uint32_t count;
  };
  // Empty, one surfel, fewer than / exactly / one more than max_nodes (stride 1 → 2), a stride that does not
  // divide the count, the whole map; both arrays.
  for (const Case c :
       {Case{0, 0}, {0, 1}, {1, 99}, {0, 100}, {0, 101}, {1, 250}, {0, 12'345}, {0, capacity}, {1, capacity}}) {
    SCOPED_TRACE("parity " + std::to_string(c.parity) + ", " + std::to_string(c.count) + " surfels");
    rig.setMap(c.parity, c.count);
    rig.sampling().sample();
    const std::span<const Surfel> live = std::span<const Surfel>(c.parity == 0 ? grown : reversed).first(c.count);

    std::vector<MapNodeSample> expected(options.max_nodes);
    const map::NodeSampleHeader header = map::sampleNodesCpu(live, options.max_nodes, expected);
    EXPECT_EQ(rig.sampling().header(), header);
    EXPECT_EQ(header.surfel_count, c.count);
    EXPECT_EQ(header.stride, map::nodeSampleStride(c.count, options.max_nodes));
    EXPECT_LE(header.sample_count, options.max_nodes);
    EXPECT_EQ(header.sample_count, (c.count + header.stride - 1) / header.stride);
    ASSERT_EQ(rig.sampling().samples().size(), header.sample_count);
    EXPECT_EQ(
        countDifferent(rig.sampling().samples(), std::span<const MapNodeSample>(expected).first(header.sample_count)),
        0u);
    for (std::uint32_t j = 0; j < header.sample_count; ++j) {
      const Surfel& s = live[std::size_t{j} * header.stride];
      ASSERT_EQ(rig.sampling().samples()[j].created_frame, static_cast<std::uint32_t>(s.colour_times.y()));
    }
  }
}

TEST_F(MapSamplingTest, NodeSamplesBuildADeformationGraphWithoutAllocating) {
  const std::vector<Surfel> grown = grownMap(60, 12);
  const map::MapSamplingOptions options;  // the defaults: 1024 nodes
  SamplingRig rig(context(), static_cast<std::uint32_t>(grown.size()), options);
  rig.writeArray(0, grown);
  rig.setMap(0, static_cast<std::uint32_t>(grown.size()));
  rig.sampling().sample();
  const map::NodeSampleHeader header = rig.sampling().header();
  EXPECT_GT(header.stride, 1u);
  EXPECT_GT(header.sample_count, options.max_nodes / 2);
  EXPECT_LE(header.sample_count, options.max_nodes);

  // Into a span the caller allocated once: max_nodes entries always suffice.
  std::vector<loop::NodeSample> samples(options.max_nodes);
  const std::size_t n = rig.sampling().readNodeSamples(samples);
  ASSERT_EQ(n, header.sample_count);
  for (std::size_t i = 0; i < n; ++i) {
    const Surfel& s = grown[i * header.stride];
    EXPECT_EQ(samples[i].p_W, s.position_confidence.head<3>().cast<double>()) << i;
    EXPECT_EQ(samples[i].time, static_cast<std::uint32_t>(s.colour_times.y())) << i;
  }
  loop::DeformationGraph graph;
  graph.build(std::span<const loop::NodeSample>(samples).first(n));
  EXPECT_EQ(graph.nodeCount(), static_cast<int>(n));

  std::vector<loop::NodeSample> too_short(n - 1);
  test::expectError([&] { rig.sampling().readNodeSamples(too_short); }, "do not fit");
}

TEST_F(MapSamplingTest, GathersTheSurfelsThatWonThePixelsOfTheActiveAndTheInactivePrediction) {
  const std::vector<Surfel> wall = test::blockWallSurfels();
  const auto count = static_cast<std::uint32_t>(wall.size());
  const map::MapSamplingOptions options = smallOptions();
  SamplingRig rig(context(), 2 * count, options);
  // As after Slam's frame: compaction wrote array 1, the predictions rendered it, Slam flipped to it. Array 0
  // holds the wall reversed: a gather of the wrong array returns other surfels.
  const std::vector<Surfel> reversed(wall.rbegin(), wall.rend());
  rig.writeArray(0, reversed);
  rig.writeArray(1, wall);
  rig.setMap(1, count);
  rig.predict();

  // Every 3rd pixel in both directions (540), pixels outside the image, and the image's far corner.
  std::vector<GatherPixel> pixels;
  for (int y = 0; y < kCamera.height; y += 3) {
    for (int x = 0; x < kCamera.width; x += 3) pixels.push_back({x, y});
  }
  for (const GatherPixel outside : {GatherPixel{-1, 0}, {0, -1}, {kCamera.width, 5}, {5, kCamera.height}}) {
    pixels.push_back(outside);
  }
  pixels.push_back({kCamera.width - 1, kCamera.height - 1});
  ASSERT_LE(pixels.size(), options.max_points);

  for (const map::PredictedSurfels set : {map::PredictedSurfels::kActive, map::PredictedSurfels::kInactive}) {
    const bool inactive = set == map::PredictedSurfels::kInactive;
    SCOPED_TRACE(inactive ? "inactive" : "active");
    map::PredictionGather& gather = rig.gather(set);
    gather.setPixels(pixels);
    gather.gather();
    ASSERT_EQ(gather.points().size(), pixels.size());

    std::vector<GatheredPoint> expected(pixels.size());
    map::gatherPointsCpu(wall, rig.ids(set), pixels, expected);
    EXPECT_EQ(countDifferent(gather.points(), std::span<const GatheredPoint>(expected)), 0u);

    // What the points are: the surfels of the prediction's set that won those pixels, none elsewhere.
    std::size_t valid = 0;
    for (std::size_t j = 0; j < pixels.size(); ++j) {
      const GatheredPoint& point = gather.points()[j];
      const GatherPixel pixel = pixels[j];
      const bool in_image = pixel.x >= 0 && pixel.y >= 0 && pixel.x < kCamera.width && pixel.y < kCamera.height;
      const std::uint32_t id = in_image ? rig.ids(set)(pixel.x, pixel.y) : map::kNoSurfel;
      if (id == map::kNoSurfel) {
        EXPECT_EQ(point.valid, 0u) << j;
        EXPECT_EQ(point.surfel, map::kNoSurfel) << j;
        continue;
      }
      ++valid;
      ASSERT_EQ(point.valid, 1u) << j;
      ASSERT_EQ(point.surfel, id) << j;
      const Surfel& s = wall[id];
      EXPECT_EQ(point.position(), s.position_confidence.head<3>()) << j;
      EXPECT_EQ(point.normal(), s.normal_radius.head<3>()) << j;
      EXPECT_EQ(point.created_frame, static_cast<std::uint32_t>(s.colour_times.y())) << j;
      EXPECT_EQ(point.updated_frame, static_cast<std::uint32_t>(s.colour_times.z())) << j;
      EXPECT_GE(s.position_confidence.w(), kStableConfidence) << j;
      EXPECT_EQ(kFrame - point.updated_frame > map::MapOptions{}.time_window_frames, inactive) << j;
      EXPECT_LT(pixel.x, 60 + 2) << j;  // nothing to the right of the wall but its rim
    }
    // A quarter of the wall's blocks per set, the wall three quarters of the image.
    EXPECT_GE(valid, pixels.size() / 8);
    EXPECT_LE(valid, pixels.size() / 2);
  }

  // Fewer pixels next time: only those are gathered.
  map::PredictionGather& gather = rig.gather(map::PredictedSurfels::kActive);
  gather.setPixels(std::span<const GatherPixel>(pixels).first(7));
  gather.gather();
  std::vector<GatheredPoint> expected(7);
  map::gatherPointsCpu(wall, rig.ids(map::PredictedSurfels::kActive), std::span<const GatherPixel>(pixels).first(7),
                       expected);
  EXPECT_EQ(countDifferent(gather.points(), std::span<const GatheredPoint>(expected)), 0u);

  const std::vector<GatherPixel> too_many(options.max_points + 1);
  test::expectError([&] { gather.setPixels(too_many); }, "at most 600 (max_points)");
}

// After build() the host side of sampling and gathering allocates nothing: no C++ heap, no Vulkan objects.
// (Not under the validation layer, which allocates on the host at every submission.)
TEST_F(MapSamplingTest, SamplesAndGathersWithoutAllocatingAfterBuild) {
  if (context().validationEnabled()) GTEST_SKIP() << "the validation layer allocates per submission";
  const std::vector<Surfel> wall = test::blockWallSurfels();
  const auto count = static_cast<std::uint32_t>(wall.size());
  const map::MapSamplingOptions options;
  SamplingRig rig(context(), count, options);
  rig.writeArray(0, wall);
  rig.setMap(0, count);
  rig.predict();
  std::vector<loop::NodeSample> samples(options.max_nodes);
  std::vector<GatherPixel> pixels;
  for (int i = 0; i < 100; ++i) pixels.push_back({(i * 7) % kCamera.width, (i * 3) % kCamera.height});
  map::PredictionGather& gather = rig.gather(map::PredictedSurfels::kInactive);
  const auto round = [&] {
    rig.sampling().sample();
    EXPECT_EQ(rig.sampling().readNodeSamples(samples), rig.sampling().header().sample_count);
    gather.setPixels(pixels);
    gather.gather();
    EXPECT_EQ(gather.points().size(), pixels.size());
  };
  round();  // first submissions: drivers may set up lazily
  const std::uint64_t heap_before = test::heapAllocationCount();
  const test::VulkanCallCounts vulkan_before = test::vulkanCallCounts();
  for (int i = 0; i < 10; ++i) round();
  EXPECT_EQ(test::heapAllocationCount(), heap_before);
  EXPECT_EQ(test::vulkanCallCounts().allocate_memory, vulkan_before.allocate_memory);
  EXPECT_EQ(test::vulkanCallCounts().create_or_update, vulkan_before.create_or_update);
}

TEST_F(MapSamplingTest, DeclaresItsBuffersPerPredictionFromThePlan) {
  SamplingRig rig(context(), 1000, map::MapSamplingOptions{});
  std::vector<std::string> names;
  for (const gpu::BufferRequest& request : rig.plan().buffers()) names.push_back(request.name);
  for (const char* name :
       {"map_sample.nodes", "map_sample.header", "map_gather.active.points", "map_gather.inactive.points",
        "map_gather.active.pixels", "map_gather.inactive.pixels", "prediction.ids", "prediction_inactive.ids"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << name;
  }
  const gpu::BufferRequest& nodes = rig.plan().buffers()[rig.sampling().samplesBuffer().index];
  EXPECT_EQ(nodes.use, gpu::MemoryUse::Readback);
  EXPECT_EQ(nodes.bytes, 1024u * sizeof(MapNodeSample));
  const gpu::BufferRequest& points =
      rig.plan().buffers()[rig.gather(map::PredictedSurfels::kInactive).pointsBuffer().index];
  EXPECT_EQ(points.use, gpu::MemoryUse::Readback);
  EXPECT_EQ(points.bytes, 1024u * sizeof(GatheredPoint));
}

TEST(MapSamplingOptions, ValidateNamesTheField) {
  const auto with = [](auto change) {
    map::MapSamplingOptions options;
    change(options);
    return [options] { options.validate(); };
  };
  EXPECT_NO_THROW(map::MapSamplingOptions{}.validate());
  test::expectError(with([](map::MapSamplingOptions& o) { o.max_nodes = 0; }), "'max_nodes' must be in 1..1000000");
  test::expectError(with([](map::MapSamplingOptions& o) { o.max_nodes = map::kMaxSamplingEntries + 1; }),
                    "'max_nodes'");
  test::expectError(with([](map::MapSamplingOptions& o) { o.max_points = 0; }), "'max_points' must be in 1..1000000");
  test::expectError(with([](map::MapSamplingOptions& o) { o.node_workgroup_size = 0; }),
                    "'node_workgroup_size' must be in 1..1024");
  test::expectError(with([](map::MapSamplingOptions& o) { o.point_workgroup_size = 1025; }),
                    "'point_workgroup_size' must be in 1..1024");
}

TEST(MapSamplingCpu, StrideKeepsTheSamplesWithinMaxNodes) {
  EXPECT_EQ(map::nodeSampleStride(0, 1024), 1u);
  EXPECT_EQ(map::nodeSampleStride(1024, 1024), 1u);
  EXPECT_EQ(map::nodeSampleStride(1025, 1024), 2u);
  EXPECT_EQ(map::nodeSampleStride(2'000'000, 1024), 1954u);
  EXPECT_EQ(map::nodeSampleStride(0xffffffffu, 1), 0xffffffffu);  // no wrap
  for (const std::uint32_t count : {1u, 7u, 1023u, 1024u, 1025u, 2048u, 2049u, 2'000'000u}) {
    const std::uint32_t stride = map::nodeSampleStride(count, 1024);
    EXPECT_LE((count + stride - 1) / stride, 1024u) << count;
  }
  const std::vector<MapNodeSample> samples(3);
  std::vector<loop::NodeSample> out(2);
  test::expectError([&] { map::toLoopNodeSamples(samples, out); }, "3 node samples do not fit into 2");
}

}  // namespace
}  // namespace vifusion
