#pragma once
// One GpuContext per test binary (device creation is the slow part), opened with the options from
// the environment, so `VIFUSION_GPU_VALIDATION=1` turns every GPU test into its validation variant.
// Any validation message during a test fails that test.

#include <gtest/gtest.h>

#include <memory>

#include "vifusion/gpu/gpu_context.hpp"

namespace vifusion::test {

/// The shared context; created on first use.
gpu::GpuContext& gpuContext();

class GpuTest : public ::testing::Test {
 protected:
  void SetUp() override;
  void TearDown() override;

  gpu::GpuContext& context() { return gpuContext(); }

 private:
  uint32_t validation_messages_before_ = 0;
};

}  // namespace vifusion::test
