#include "gpu_test_environment.hpp"

#include <cstdlib>
#include <cstring>

namespace vifusion::test {

gpu::GpuContext& gpuContext() {
  static std::unique_ptr<gpu::GpuContext> context = gpu::GpuContext::create(gpu::GpuOptions{}.withEnvironment());
  return *context;
}

void GpuTest::SetUp() {
  // The validation variant must really run with the layer: a silently missing layer would pass.
  const char* validation = std::getenv("VIFUSION_GPU_VALIDATION");
  if (validation != nullptr && std::strcmp(validation, "1") == 0) {
    ASSERT_TRUE(context().validationEnabled()) << "VIFUSION_GPU_VALIDATION=1 but the layer is not active";
  }
  validation_messages_before_ = context().validationMessageCount();
}

void GpuTest::TearDown() {
  EXPECT_EQ(context().validationMessageCount(), validation_messages_before_)
      << "validation layer reported: " << context().firstValidationMessage();
}

}  // namespace vifusion::test
