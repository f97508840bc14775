// gpu::TimestampPool: GPU time between two points of a recorded sequence, within the host's wall time of the
// same submission; slots that were not written read as not valid; slots beyond the pool are refused at record
// time. On a device without timestamps (none in CI: lavapipe has them) the pool reports unavailable.

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <chrono>
#include <cstdio>

#include "gpu_test_environment.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/gpu/compute_kernel.hpp"
#include "vifusion/gpu/timestamp_pool.hpp"
#include "vifusion/test_shaders/spirv.hpp"

namespace vifusion {
namespace {

using test::GpuTest;

struct ScaleAddPush {
  uint32_t count;
  float scale;
};

TEST_F(GpuTest, TimestampsMeasureTheWorkBetweenThemWithinTheHostsWallTime) {
  constexpr uint32_t kCount = 1u << 20;
  constexpr int kDispatches = 20;
  gpu::CapacityPlan plan;
  const auto a = plan.addBuffer("a", kCount * sizeof(float), gpu::MemoryUse::DeviceLocal);
  const auto b = plan.addBuffer("b", kCount * sizeof(float), gpu::MemoryUse::DeviceLocal);
  const auto arena = gpu::MemoryArena::create(context(), plan);
  gpu::KernelSpec spec;
  spec.name = "scale_add";
  spec.spirv = test_shaders::scale_add;
  spec.storage_buffers = 2;
  spec.push_constant_bytes = sizeof(ScaleAddPush);
  spec.workgroup_size = {64, 1, 1};
  spec.constants = {{3, std::bit_cast<uint32_t>(1.0f)}};
  auto kernel = gpu::ComputeKernel::create(context(), std::move(spec));
  const gpu::BindingSet set = kernel->bind({&arena->buffer(a), &arena->buffer(b)});

  gpu::TimestampPool pool(context(), 4);
  EXPECT_EQ(pool.available(), context().features().timestamp_valid_bits > 0);
  auto sequence = gpu::CommandSequence::create(context(), "timed");
  sequence->record([&](gpu::CommandRecorder& recorder) {
    pool.recordReset(recorder, 0, 4);
    pool.recordWrite(recorder, 0);
    pool.recordWrite(recorder, 1);  // nothing between 0 and 1
    for (int i = 0; i < kDispatches; ++i) {
      recorder.dispatch(*kernel, set, {kCount / 64, 1, 1}, ScaleAddPush{kCount, 0.5f});
      recorder.computeBarrier();
    }
    pool.recordWrite(recorder, 2);  // slot 3 is reset but never written
    recorder.hostReadBarrier();
  });
  const auto start = std::chrono::steady_clock::now();
  sequence->run();
  const double host_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (!pool.available()) GTEST_SKIP() << "the device has no timestamps on its compute queue";

  std::array<std::uint64_t, 3> ticks{};
  ASSERT_TRUE(pool.read(0, ticks));
  const double empty_ms = pool.msBetween(ticks[0], ticks[1]);
  const double work_ms = pool.msBetween(ticks[1], ticks[2]);
  std::printf("%d dispatches over %u floats: %.3f ms on the GPU, %.3f ms on the host; empty interval %.4f ms\n",
              kDispatches, kCount, work_ms, host_ms, empty_ms);
  EXPECT_GE(empty_ms, 0.0);
  EXPECT_GT(work_ms, 0.0);
  EXPECT_LE(work_ms, host_ms);
  EXPECT_LT(empty_ms, work_ms);
  std::array<std::uint64_t, 2> unwritten{};
  EXPECT_FALSE(pool.read(2, unwritten)) << "slot 3 was never written";

  auto bad = gpu::CommandSequence::create(context(), "bad");
  EXPECT_THROW(bad->record([&](gpu::CommandRecorder& recorder) { pool.recordWrite(recorder, 4); }), Error);
}

}  // namespace
}  // namespace vifusion
