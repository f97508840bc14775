#include <gtest/gtest.h>

#include <cstring>
#include <set>

#include "gpu_test_environment.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/gpu/capacity_plan.hpp"
#include "vifusion/gpu/memory_arena.hpp"

namespace vifusion {
namespace {

using test::GpuTest;

std::string planError(const gpu::GpuContext& context, const gpu::CapacityPlan& plan) {
  try {
    gpu::MemoryArena::create(context, plan);
  } catch (const Error& error) {
    return error.what();
  }
  return {};
}

TEST_F(GpuTest, AnInvalidPlanListsEveryProblemBeforeAllocating) {
  gpu::CapacityPlan plan;
  plan.addBuffer("a", 0, gpu::MemoryUse::DeviceLocal);
  plan.addBuffer("b", 64, gpu::MemoryUse::Upload);
  plan.addBuffer("b", 64, gpu::MemoryUse::Readback);
  plan.addBuffer("huge", context().features().max_storage_buffer_range_bytes + 4, gpu::MemoryUse::DeviceLocal);
  const std::string message = planError(context(), plan);
  EXPECT_NE(message.find("buffer 'a' has size 0"), std::string::npos) << message;
  EXPECT_NE(message.find("buffer 'b' is declared twice"), std::string::npos) << message;
  EXPECT_NE(message.find("buffer 'huge' needs"), std::string::npos) << message;
}

TEST_F(GpuTest, AnEmptyPlanIsRejected) {
  EXPECT_NE(planError(context(), gpu::CapacityPlan{}).find("no buffers"), std::string::npos);
}

TEST_F(GpuTest, APlanLargerThanTheDeviceIsRejected) {
  gpu::CapacityPlan plan;
  const uint64_t chunk = context().features().max_storage_buffer_range_bytes;
  // More chunks than any heap of this device can hold (heaps are at most a few TiB).
  for (int i = 0; i < 40000; ++i) plan.addBuffer("chunk" + std::to_string(i), chunk, gpu::MemoryUse::DeviceLocal);
  EXPECT_NE(planError(context(), plan).find("largest suitable memory heap"), std::string::npos);
}

TEST_F(GpuTest, ArenaMakesOneAllocationPerMemoryKindAndBuffersDoNotOverlap) {
  gpu::CapacityPlan plan;
  std::vector<gpu::BufferId> ids;
  for (int i = 0; i < 12; ++i) {
    const auto use = static_cast<gpu::MemoryUse>(i % 3);
    ids.push_back(plan.addBuffer("buffer" + std::to_string(i), 1000 + 37 * i, use));
  }
  const auto arena = gpu::MemoryArena::create(context(), plan);

  std::set<uint32_t> memory_types;
  uint32_t buffers_in_blocks = 0;
  for (const gpu::ArenaBlock& block : arena->blocks()) {
    EXPECT_TRUE(memory_types.insert(block.memory_type).second) << "two allocations of one memory type";
    buffers_in_blocks += block.buffer_count;
  }
  EXPECT_LE(arena->blocks().size(), 3u);
  EXPECT_EQ(buffers_in_blocks, ids.size());
  EXPECT_GE(arena->allocatedBytes(), plan.totalBytes());

  // Fill every host-visible buffer with its own byte, then check none was overwritten.
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const gpu::GpuBuffer& buffer = arena->buffer(ids[i]);
    if (buffer.mapped != nullptr) std::memset(buffer.mapped, static_cast<int>(i + 1), buffer.bytes);
  }
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const gpu::GpuBuffer& buffer = arena->buffer(ids[i]);
    if (buffer.mapped == nullptr) continue;
    for (uint64_t byte = 0; byte < buffer.bytes; ++byte) {
      ASSERT_EQ(static_cast<int>(buffer.mapped[byte]), static_cast<int>(i + 1)) << buffer.name << " byte " << byte;
    }
  }
  // Upload and readback buffers are always host-visible.
  EXPECT_NE(arena->buffer(ids[1]).mapped, nullptr);
  EXPECT_NE(arena->buffer(ids[2]).mapped, nullptr);
  EXPECT_THROW(arena->buffer(gpu::BufferId{}), Error);
}

}  // namespace
}  // namespace vifusion
