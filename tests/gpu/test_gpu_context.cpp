#include <gtest/gtest.h>

#include <cstdlib>
#include <optional>
#include <string>

#include "gpu_test_environment.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/gpu/gpu_context.hpp"

namespace vifusion {
namespace {

using test::GpuTest;

TEST_F(GpuTest, PicksAUsableDeviceAndQueriesItsFeatures) {
  const gpu::GpuFeatures& features = context().features();
  EXPECT_FALSE(features.device_name.empty());
  EXPECT_GE(features.api_version, VK_API_VERSION_1_2);
  EXPECT_GE(features.max_push_constants_bytes, 128u);  // Vulkan guarantees 128 bytes
  EXPECT_GE(features.max_workgroup_invocations, 128u);
  EXPECT_GT(features.max_storage_buffer_range_bytes, 0u);
  EXPECT_GT(features.subgroup_size, 0u);
  EXPECT_NE(context().device(), VK_NULL_HANDLE);
  EXPECT_NE(context().queue(), VK_NULL_HANDLE);
  std::cout << "device: " << features.device_name << " (" << gpu::deviceTypeName(features.device_type) << "), subgroup "
            << features.subgroup_size << (features.subgroup_arithmetic ? " with" : " without") << " arithmetic, fp64 "
            << features.float64 << ", float atomics " << features.float32_atomic_add << ", unified memory "
            << features.unified_memory << "\n";
}

TEST_F(GpuTest, HonoursADeviceNameOverride) {
  gpu::GpuOptions options;
  options.device = context().features().device_name.substr(0, 4);  // any part of the name, any case
  const auto other = gpu::GpuContext::create(options);
  EXPECT_EQ(other->features().device_name, context().features().device_name);
}

TEST_F(GpuTest, AnUnknownDeviceNameListsTheDevicesFound) {
  gpu::GpuOptions options;
  options.device = "no-such-gpu-9000";
  try {
    gpu::GpuContext::create(options);
    FAIL() << "expected an error";
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("no-such-gpu-9000"), std::string::npos) << message;
    EXPECT_NE(message.find(context().features().device_name), std::string::npos) << message;
  }
}

TEST_F(GpuTest, DisablingSubgroupArithmeticIsReflectedInTheFeatures) {
  gpu::GpuOptions options;
  options.device = context().features().device_name;
  options.disable_subgroup_arithmetic = true;
  EXPECT_FALSE(gpu::GpuContext::create(options)->features().subgroup_arithmetic);
}

TEST(GpuOptions, RejectsAMistypedEnvironmentSwitch) {
  setenv("VIFUSION_GPU_VALIDATION", "yes please", 1);
  EXPECT_THROW(gpu::GpuOptions{}.withEnvironment(), Error);
  unsetenv("VIFUSION_GPU_VALIDATION");
}

/// Sets an environment variable for a scope, restoring what was there (the whole binary run by hand shares one
/// environment; ctest runs each case in its own process).
class ScopedEnvironment {
 public:
  ScopedEnvironment(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    setenv(name, value, 1);
  }
  ~ScopedEnvironment() {
    if (old_) {
      setenv(name_, old_->c_str(), 1);
    } else {
      unsetenv(name_);
    }
  }
  ScopedEnvironment(const ScopedEnvironment&) = delete;
  ScopedEnvironment& operator=(const ScopedEnvironment&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

// ctest runs every test case in its own process, so pointing the loader at a missing driver here
// is the first Vulkan call of the process.
TEST(GpuContextMissingDevice, SaysThatNoDriverWasFound) {
  const ScopedEnvironment icd("VK_ICD_FILENAMES", "/nonexistent/vifusion_icd.json");
  const ScopedEnvironment driver_files("VK_DRIVER_FILES", "/nonexistent/vifusion_icd.json");
  try {
    gpu::GpuContext::create(gpu::GpuOptions{});
    FAIL() << "expected an error without any Vulkan driver";
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("no Vulkan"), std::string::npos) << message;
    EXPECT_NE(message.find("mesa-vulkan-drivers"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace vifusion
