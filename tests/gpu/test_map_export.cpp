// Map export on the GPU against its CPU reference: chunk by chunk through a small staging buffer,
// from either ping-pong array, exactly the live surfels [0, surfel_count) in map order, bit for bit
// (the surfels are random words: NaN payloads, infinities and denormals included), and nothing
// beyond surfel_count is ever copied. Also the staging buffer's size and the options' validation.

#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "gpu_test_environment.hpp"
#include "random_surfels.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/map/export_cpu.hpp"
#include "vifusion/map/map_buffers.hpp"
#include "vifusion/map/map_export.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion {
namespace {

using map::Surfel;

const PinholeCamera kCamera = PinholeCamera::create(64, 48, 50, 50, 32, 24);  ///< index map only

map::MapOptions mapOptions(std::uint32_t capacity) {
  map::MapOptions options;
  options.capacity = capacity;
  return options;
}

map::ExportOptions exportOptions(std::uint32_t chunk_surfels) {
  map::ExportOptions options;
  options.chunk_surfels = chunk_surfels;
  options.workgroups = 3;  // fewer invocations than a chunk: the grid-stride loop runs several times
  options.workgroup_size = 64;
  return options;
}

using test::randomSurfels;
using test::sameBits;

/// A map with its export on one arena, plus an upload buffer that writes either surfel array.
class ExportRig {
 public:
  ExportRig(gpu::GpuContext& context, std::uint32_t capacity, std::uint32_t chunk_surfels)
      : map_(plan_, mapOptions(capacity), kCamera), export_(context, plan_, map_, exportOptions(chunk_surfels)) {
    const std::uint64_t surfel_bytes = std::uint64_t{capacity} * sizeof(Surfel);
    upload_ = plan_.addBuffer("test.surfels", surfel_bytes, gpu::MemoryUse::Upload);
    arena_ = gpu::MemoryArena::create(context, plan_);
    export_.build(*arena_);
    map_.reset(*arena_);
    for (int parity = 0; parity < 2; ++parity) {
      uploads_[parity] = gpu::CommandSequence::create(context, "upload " + std::to_string(parity));
      uploads_[parity]->record([&](gpu::CommandRecorder& r) {
        r.copyBuffer(arena_->buffer(upload_), arena_->buffer(map_.surfels(parity)), surfel_bytes);
        r.computeBarrier();
      });
    }
  }

  /// Fills surfel array `parity` (capacity entries).
  void writeArray(int parity, std::span<const Surfel> surfels) {
    std::memcpy(arena_->buffer(upload_).mapped, surfels.data(), surfels.size_bytes());
    uploads_[parity]->run();
  }
  /// Makes array `parity` the current one holding `count` live surfels.
  void setMap(int parity, std::uint32_t count) {
    if (map_.current() != parity) map_.flip();
    map::MapState state;
    state.surfel_count = count;
    std::memcpy(arena_->buffer(map_.state()).mapped, &state, sizeof(state));
  }
  map::MapExport& exporter() { return export_; }
  std::span<Surfel> stagingMemory() const { return arena_->buffer(export_.staging()).hostSpan<Surfel>(); }

 private:
  gpu::CapacityPlan plan_;
  map::MapBuffers map_;
  map::MapExport export_;
  gpu::BufferId upload_;
  std::unique_ptr<gpu::MemoryArena> arena_;
  std::unique_ptr<gpu::CommandSequence> uploads_[2];
};

class MapExportTest : public test::GpuTest {};

TEST_F(MapExportTest, ReadsExactlyTheLiveSurfelsOfEitherArrayInOrderChunkByChunk) {
  constexpr std::uint32_t kCapacity = 5000;
  constexpr std::uint32_t kChunk = 1000;
  ExportRig rig(context(), kCapacity, kChunk);
  const std::vector<Surfel> arrays[2] = {randomSurfels(kCapacity, 1), randomSurfels(kCapacity, 2)};
  rig.writeArray(0, arrays[0]);
  rig.writeArray(1, arrays[1]);

  struct Case {
    int parity;
    std::uint32_t count;
  };
  // Partial last chunks, whole chunks, a full map, one surfel, an empty map; both parities, flipping.
  for (const Case c : {Case{0, 3456}, {1, 4321}, {1, kCapacity}, {0, 2000}, {1, 1}, {0, 0}, {1, 999}}) {
    SCOPED_TRACE("parity " + std::to_string(c.parity) + ", " + std::to_string(c.count) + " surfels");
    rig.setMap(c.parity, c.count);
    const std::vector<Surfel>& array = arrays[c.parity];

    // Chunk by chunk against the CPU reference.
    std::vector<Surfel> expected_chunk(kChunk);
    std::uint32_t next_first = 0;
    const std::uint32_t visited = rig.exporter().visitChunks([&](std::uint32_t first, std::span<const Surfel> chunk) {
      EXPECT_EQ(first, next_first);
      const std::uint32_t n = map::exportChunkCpu(array, c.count, {first, kChunk}, expected_chunk);
      EXPECT_EQ(chunk.size(), n);
      EXPECT_TRUE(sameBits(chunk, std::span<const Surfel>(expected_chunk).first(n))) << "chunk at " << first;
      next_first = first + kChunk;
    });
    EXPECT_EQ(visited, c.count);
    EXPECT_EQ(next_first, (c.count + kChunk - 1) / kChunk * kChunk);  // every chunk, none past the end

    // The whole map: the live prefix of the current array, nothing more.
    std::vector<Surfel> surfels(7, Surfel{});  // stale contents are replaced
    rig.exporter().read(surfels);
    ASSERT_EQ(surfels.size(), c.count);
    EXPECT_TRUE(sameBits(surfels, std::span<const Surfel>(array).first(c.count)));
  }
}

TEST_F(MapExportTest, NeverCopiesSurfelsBeyondTheSurfelCount) {
  constexpr std::uint32_t kCapacity = 5000;
  constexpr std::uint32_t kChunk = 1000;
  ExportRig rig(context(), kCapacity, kChunk);
  const std::vector<Surfel> array = randomSurfels(kCapacity, 3);  // beyond the count: live-looking data
  rig.writeArray(1, array);
  rig.setMap(1, 3456);
  const std::vector<Surfel> sentinel = randomSurfels(kChunk, 4);
  const auto staging = rig.stagingMemory();
  ASSERT_EQ(staging.size(), kChunk);

  // The last, partial chunk: 456 surfels; the staging buffer's other 544 entries are not written.
  std::memcpy(static_cast<void*>(staging.data()), sentinel.data(), staging.size_bytes());
  const std::span<const Surfel> last = rig.exporter().readChunk(3000);
  ASSERT_EQ(last.size(), 456u);
  EXPECT_TRUE(sameBits(last, std::span<const Surfel>(array).subspan(3000, 456)));
  EXPECT_TRUE(sameBits(staging.subspan(456), std::span<const Surfel>(sentinel).subspan(456)));

  // At and past the end (still inside the capacity): nothing at all.
  for (const std::uint32_t first : {3456u, 4000u}) {
    SCOPED_TRACE("first " + std::to_string(first));
    std::memcpy(static_cast<void*>(staging.data()), sentinel.data(), staging.size_bytes());
    EXPECT_TRUE(rig.exporter().readChunk(first).empty());
    EXPECT_TRUE(sameBits(staging, sentinel));
  }
}

TEST_F(MapExportTest, StagesOneChunkNotTheWholeMap) {
  // The default 2 M-surfel map (96 MiB per array) reads back through 3 MiB.
  gpu::CapacityPlan plan;
  const map::MapBuffers map(plan, map::MapOptions{}, kCamera);
  const map::MapExport exporter(context(), plan, map);
  EXPECT_EQ(exporter.chunkSurfels(), 65'536u);
  std::uint64_t readback_bytes = 0;
  for (const gpu::BufferRequest& request : plan.buffers()) {
    if (request.use == gpu::MemoryUse::Readback) readback_bytes += request.bytes;
  }
  EXPECT_EQ(readback_bytes, 3u << 20);
  EXPECT_EQ(plan.buffers()[exporter.staging().index].name, "map_export.staging");

  // A chunk larger than the map is cut to the map's capacity.
  gpu::CapacityPlan small_plan;
  const map::MapBuffers small_map(small_plan, mapOptions(500), kCamera);
  const map::MapExport small_exporter(context(), small_plan, small_map);
  EXPECT_EQ(small_exporter.chunkSurfels(), 500u);
  EXPECT_EQ(small_plan.buffers()[small_exporter.staging().index].bytes, 500u * sizeof(Surfel));
}

TEST(MapExportOptions, ValidateNamesTheField) {
  const auto with = [](auto change) {
    map::ExportOptions options;
    change(options);
    return [options] { options.validate(); };
  };
  EXPECT_NO_THROW(map::ExportOptions{}.validate());
  test::expectError(with([](map::ExportOptions& o) { o.chunk_surfels = 0; }), "'chunk_surfels' must be ≥ 1");
  test::expectError(with([](map::ExportOptions& o) { o.workgroups = 0; }), "'workgroups' must be ≥ 1");
  test::expectError(with([](map::ExportOptions& o) { o.workgroup_size = 0; }), "'workgroup_size' must be in 1..1024");
  test::expectError(with([](map::ExportOptions& o) { o.workgroup_size = 1025; }), "'workgroup_size'");
}

TEST(MapExportCpu, ChunksAreClippedToTheSurfelCount) {
  EXPECT_EQ(map::exportChunkSize(3456, {0, 1000}), 1000u);
  EXPECT_EQ(map::exportChunkSize(3456, {3000, 1000}), 456u);
  EXPECT_EQ(map::exportChunkSize(3456, {3456, 1000}), 0u);
  EXPECT_EQ(map::exportChunkSize(3456, {4000, 1000}), 0u);
  EXPECT_EQ(map::exportChunkSize(0, {0, 1000}), 0u);
  // A chunk that would run past 2^32 does not wrap.
  EXPECT_EQ(map::exportChunkSize(1u << 26, {(1u << 26) - 5, 0xffffffffu}), 5u);

  const std::vector<Surfel> surfels = randomSurfels(10, 5);
  std::vector<Surfel> staging = randomSurfels(4, 6);
  const std::vector<Surfel> before = staging;
  EXPECT_EQ(map::exportChunkCpu(surfels, 7, {4, 4}, staging), 3u);
  EXPECT_TRUE(sameBits(std::span<const Surfel>(staging).first(3), std::span<const Surfel>(surfels).subspan(4, 3)));
  EXPECT_TRUE(sameBits(std::span<const Surfel>(staging).subspan(3), std::span<const Surfel>(before).subspan(3)));
}

}  // namespace
}  // namespace vifusion
