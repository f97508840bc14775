#include <gtest/gtest.h>

#include <bit>
#include <vector>

#include "gpu_test_environment.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/gpu/compute_kernel.hpp"
#include "vifusion/test_shaders/spirv.hpp"

namespace vifusion {
namespace {

using test::GpuTest;

struct ScaleAddPush {
  uint32_t count;
  float scale;
};

gpu::KernelSpec scaleAddSpec(float offset) {
  gpu::KernelSpec spec;
  spec.name = "scale_add";
  spec.spirv = test_shaders::scale_add;
  spec.storage_buffers = 2;
  spec.push_constant_bytes = sizeof(ScaleAddPush);
  spec.workgroup_size = {64, 1, 1};
  spec.constants = {{3, std::bit_cast<uint32_t>(offset)}};
  return spec;
}

std::string kernelError(const gpu::GpuContext& context, gpu::KernelSpec spec) {
  try {
    gpu::ComputeKernel::create(context, std::move(spec));
  } catch (const Error& error) {
    return error.what();
  }
  return {};
}

TEST_F(GpuTest, RecordedOnceSubmittedManyTimesWithPushAndSpecializationConstants) {
  constexpr uint32_t kCount = 1000;
  gpu::CapacityPlan plan;
  const auto in_id = plan.addBuffer("in", kCount * sizeof(float), gpu::MemoryUse::Upload);
  const auto out_id = plan.addBuffer("out", kCount * sizeof(float), gpu::MemoryUse::Readback);
  const auto arena = gpu::MemoryArena::create(context(), plan);
  auto kernel = gpu::ComputeKernel::create(context(), scaleAddSpec(0.5f));
  const gpu::BindingSet set = kernel->bind({&arena->buffer(in_id), &arena->buffer(out_id)});
  auto sequence = gpu::CommandSequence::create(context(), "scale_add");
  sequence->record([&](gpu::CommandRecorder& recorder) {
    recorder.dispatch(*kernel, set, {(kCount + 63) / 64, 1, 1}, ScaleAddPush{kCount, 3.0f});
    recorder.hostReadBarrier();
  });

  const auto in = arena->buffer(in_id).hostSpan<float>();
  const auto out = arena->buffer(out_id).hostSpan<const float>();
  for (int frame = 1; frame <= 3; ++frame) {
    for (uint32_t i = 0; i < kCount; ++i) in[i] = static_cast<float>(i * frame);
    const uint64_t ticket = sequence->submit();
    EXPECT_EQ(ticket, static_cast<uint64_t>(frame));  // the timeline counts submissions
    sequence->wait(ticket);
    EXPECT_TRUE(sequence->isComplete(ticket));
    for (uint32_t i = 0; i < kCount; ++i) ASSERT_FLOAT_EQ(out[i], 3.0f * static_cast<float>(i * frame) + 0.5f);
  }
}

TEST_F(GpuTest, CorruptSpirvIsRejectedWithTheShaderName) {
  const std::vector<uint32_t> garbage = {0xdeadbeef, 1, 2, 3, 4, 5};
  gpu::KernelSpec spec = scaleAddSpec(0.0f);
  spec.name = "broken_shader";
  spec.spirv = garbage;
  const std::string message = kernelError(context(), spec);
  EXPECT_NE(message.find("broken_shader"), std::string::npos) << message;
  EXPECT_NE(message.find("bad magic"), std::string::npos) << message;

  spec.spirv = test_shaders::scale_add.first(3);
  EXPECT_NE(kernelError(context(), spec).find("truncated"), std::string::npos);
}

TEST_F(GpuTest, LimitsAreCheckedBeforeTheDriverSeesTheKernel) {
  gpu::KernelSpec too_much_push = scaleAddSpec(0.0f);
  too_much_push.push_constant_bytes = context().features().max_push_constants_bytes + 4;
  EXPECT_NE(kernelError(context(), too_much_push).find("push constants"), std::string::npos);

  gpu::KernelSpec too_wide = scaleAddSpec(0.0f);
  too_wide.workgroup_size = {context().features().max_workgroup_invocations + 1, 1, 1};
  EXPECT_NE(kernelError(context(), too_wide).find("workgroup"), std::string::npos);
}

TEST_F(GpuTest, BindingMoreSetsThanPlannedOrTheWrongBufferCountFails) {
  gpu::CapacityPlan plan;
  const auto a = plan.addBuffer("a", 256, gpu::MemoryUse::DeviceLocal);
  const auto arena = gpu::MemoryArena::create(context(), plan);
  auto kernel = gpu::ComputeKernel::create(context(), scaleAddSpec(0.0f));
  EXPECT_THROW(kernel->bind({&arena->buffer(a)}), Error);
  kernel->bind({&arena->buffer(a), &arena->buffer(a)});
  EXPECT_THROW(kernel->bind({&arena->buffer(a), &arena->buffer(a)}), Error);
}

TEST_F(GpuTest, SubmittingAnEmptySequenceIsAnError) {
  auto sequence = gpu::CommandSequence::create(context(), "empty");
  EXPECT_THROW(sequence->submit(), Error);
}

TEST(GpuDeviceLoss, EverySubmitAfterTheLossFailsNamingItAndEarlierWorkStillCompletes) {
  // A context of its own: a lost device stays lost, and the shared one serves the other tests.
  const auto lost = gpu::GpuContext::create(gpu::GpuOptions{}.withEnvironment());
  constexpr uint32_t kCount = 64;
  gpu::CapacityPlan plan;
  const auto buffer = plan.addBuffer("values", kCount * sizeof(float), gpu::MemoryUse::Readback);
  const auto arena = gpu::MemoryArena::create(*lost, plan);
  auto kernel = gpu::ComputeKernel::create(*lost, scaleAddSpec(1.0f));
  const gpu::BindingSet set = kernel->bind({&arena->buffer(buffer), &arena->buffer(buffer)});
  auto sequence = gpu::CommandSequence::create(*lost, "before_and_after_the_loss");
  sequence->record([&](gpu::CommandRecorder& recorder) {
    recorder.dispatch(*kernel, set, {1, 1, 1}, ScaleAddPush{kCount, 1.0f});
    recorder.hostReadBarrier();
  });
  const uint64_t before = sequence->submit();
  EXPECT_FALSE(lost->deviceLost());

  lost->simulateDeviceLoss();
  EXPECT_TRUE(lost->deviceLost());
  for (int attempt = 0; attempt < 2; ++attempt) {  // lost stays lost
    try {
      sequence->submit();
      ADD_FAILURE() << "a submit after the loss succeeded";
    } catch (const Error& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find("VK_ERROR_DEVICE_LOST"), std::string::npos) << message;
      EXPECT_NE(message.find("before_and_after_the_loss"), std::string::npos) << message;
    }
  }
  sequence->wait(before);  // submitted before the loss: it completes, so teardown never waits forever
  EXPECT_TRUE(sequence->isComplete(before));
  EXPECT_EQ(lost->validationMessageCount(), 0u) << lost->firstValidationMessage();
}

}  // namespace
}  // namespace vifusion
