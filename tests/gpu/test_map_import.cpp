// Map import on the GPU against its CPU reference: a loaded map written chunk by chunk through a small staging
// buffer into either ping-pong array, read back by the export bit for bit (random words: NaN payloads and
// denormals included), the map state it leaves, and the refusals (over capacity, a filler that throws).

#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <random>
#include <span>
#include <stdexcept>
#include <vector>

#include "gpu_test_environment.hpp"
#include "random_surfels.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/map/import_cpu.hpp"
#include "vifusion/map/map_buffers.hpp"
#include "vifusion/map/map_export.hpp"
#include "vifusion/map/map_import.hpp"

namespace vifusion {
namespace {

using map::Surfel;

const PinholeCamera kCamera = PinholeCamera::create(64, 48, 50, 50, 32, 24);  ///< index map only

using test::randomSurfels;
using test::sameBits;

/// A map with its import and export on one arena.
class ImportRig {
 public:
  ImportRig(gpu::GpuContext& context, std::uint32_t capacity, std::uint32_t chunk_surfels)
      : map_(plan_, options(capacity), kCamera),
        import_(context, plan_, map_, chunking(chunk_surfels)),
        export_(context, plan_, map_, chunking(chunk_surfels)) {
    arena_ = gpu::MemoryArena::create(context, plan_);
    import_.build(*arena_);
    export_.build(*arena_);
    map_.reset(*arena_);
  }
  map::MapBuffers& map() { return map_; }
  map::MapImport& importer() { return import_; }
  map::MapExport& exporter() { return export_; }
  const gpu::MemoryArena& arena() const { return *arena_; }

 private:
  static map::MapOptions options(std::uint32_t capacity) {
    map::MapOptions o;
    o.capacity = capacity;
    return o;
  }
  static map::ExportOptions chunking(std::uint32_t chunk_surfels) {
    map::ExportOptions o;
    o.chunk_surfels = chunk_surfels;
    o.workgroups = 3;  // fewer invocations than a chunk: the grid-stride loop runs several times
    o.workgroup_size = 64;
    return o;
  }
  gpu::CapacityPlan plan_;
  map::MapBuffers map_;
  map::MapImport import_;
  map::MapExport export_;
  std::unique_ptr<gpu::MemoryArena> arena_;
};

class MapImportTest : public test::GpuTest {};

TEST_F(MapImportTest, WritesTheLoadedSurfelsIntoEitherArrayBitForBit) {
  constexpr std::uint32_t kCapacity = 5000, kChunk = 1000;
  ImportRig rig(context(), kCapacity, kChunk);
  // Partial last chunk, whole chunks, a full map, one surfel, none; the second load into the other array.
  std::uint32_t seed = 1;
  for (const std::uint32_t count : {3456u, 2000u, kCapacity, 1u, 0u, 999u}) {
    for (int parity = 0; parity < 2; ++parity) {
      SCOPED_TRACE(std::to_string(count) + " surfels into array " + std::to_string(parity));
      if (rig.map().current() != parity) rig.map().flip();
      const std::vector<Surfel> loaded = randomSurfels(count, ++seed);
      std::vector<Surfel> expected = randomSurfels(kCapacity, 1000 + seed);  // the CPU reference's array
      std::uint32_t next_first = 0;
      rig.importer().load(count, 321, [&](std::uint32_t first, std::span<Surfel> chunk) {
        EXPECT_EQ(first, next_first);
        EXPECT_EQ(chunk.size(), std::min(kChunk, count - first));
        std::copy_n(loaded.begin() + first, chunk.size(), chunk.begin());
        map::importChunkCpu(chunk, {first, static_cast<std::uint32_t>(chunk.size())}, expected);
        next_first = first + kChunk;
      });
      const map::MapState state = rig.map().readState(rig.arena());
      EXPECT_EQ(state.surfel_count, count);
      EXPECT_EQ(state.frame, 321u);
      EXPECT_EQ(state.active_begin, 0u);  // the next frame sorts active from inactive
      EXPECT_EQ(state.overflow_count, 0u);
      EXPECT_EQ(rig.map().current(), parity);
      std::vector<Surfel> read;
      rig.exporter().read(read);
      EXPECT_TRUE(sameBits(read, loaded));
      EXPECT_TRUE(sameBits(std::span<const Surfel>(expected).first(count), loaded));
    }
  }
}

TEST_F(MapImportTest, RefusesAMapLargerThanTheCapacityAndEmptiesTheMapWhenTheFillerFails) {
  ImportRig rig(context(), 4096, 1000);
  rig.importer().load(100, 5,
                      [](std::uint32_t, std::span<Surfel> chunk) { std::fill(chunk.begin(), chunk.end(), Surfel{}); });
  try {
    rig.importer().load(4097, 5, [](std::uint32_t, std::span<Surfel>) { FAIL() << "filled"; });
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_STREQ(error.what(), "map import: 4097 surfels do not fit a map of capacity 4096");
  }
  EXPECT_EQ(rig.map().readState(rig.arena()).surfel_count, 100u);  // nothing written
  EXPECT_THROW(rig.importer().load(2500, 5,
                                   [](std::uint32_t first, std::span<Surfel>) {
                                     if (first > 0) throw std::runtime_error("the file was cut");
                                   }),
               std::runtime_error);
  EXPECT_EQ(rig.map().readState(rig.arena()).surfel_count, 0u);
}

}  // namespace
}  // namespace vifusion
