#pragma once
// The Vulkan instance, the chosen physical device, its logical device and compute queue.
// Created once at start-up; everything else in pipeline/gpu borrows it.

#include <vulkan/vulkan.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "vifusion/gpu/gpu_options.hpp"

namespace vifusion::gpu {

/// What the chosen device can do, as queried at start-up (optional features select kernel variants).
struct GpuFeatures {
  std::string device_name;
  VkPhysicalDeviceType device_type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
  uint32_t api_version = 0;
  std::string driver_info;

  bool subgroup_arithmetic = false;  ///< subgroupAdd etc. in compute shaders
  uint32_t subgroup_size = 0;        ///< invocations per subgroup (lavapipe 8, Mali 16, NVIDIA 32)
  bool float32_atomic_add = false;   ///< VK_EXT_shader_atomic_float on storage buffers (queried, unused)
  bool float64 = false;              ///< shaderFloat64 (queried; kernels never rely on it, V3D lacks it)
  /// shaderInt64 and shaderBufferInt64Atomics, enabled on the device when present (and not disabled
  /// by GpuOptions): kernels with a 64-bit atomicMin variant use it instead of two 32-bit passes.
  bool int64_atomics = false;

  uint32_t max_push_constants_bytes = 0;
  uint64_t max_storage_buffer_range_bytes = 0;
  uint32_t max_workgroup_invocations = 0;
  uint32_t max_shared_memory_bytes = 0;
  uint32_t max_memory_allocations = 0;
  bool unified_memory = false;  ///< a memory type is both DEVICE_LOCAL and HOST_VISIBLE
  /// Valid bits of the compute queue's timestamps (0: no timestamp queries, callers time on the CPU)
  uint32_t timestamp_valid_bits = 0;
  double timestamp_period_ns = 0.0;  ///< nanoseconds per timestamp tick (limits.timestampPeriod)
};

const char* deviceTypeName(VkPhysicalDeviceType type);

/// Counts validation-layer messages (warnings and errors); tests fail on any.
struct ValidationCounter {
  std::atomic<uint32_t> messages{0};
  std::mutex mutex;
  std::string first_message;  ///< kept for the failure report
};

class GpuContext {
 public:
  /// Opens the device. Throws vifusion::Error naming the problem: no Vulkan loader or device,
  /// no device matching GpuOptions::device (with the list of devices found), Vulkan < 1.2, no
  /// timeline semaphores, validation requested but the layer is not installed.
  static std::unique_ptr<GpuContext> create(const GpuOptions& options);
  ~GpuContext();
  GpuContext(const GpuContext&) = delete;
  GpuContext& operator=(const GpuContext&) = delete;

  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physicalDevice() const { return physical_device_; }
  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  uint32_t queueFamily() const { return queue_family_; }
  const GpuFeatures& features() const { return features_; }
  const VkPhysicalDeviceMemoryProperties& memoryProperties() const { return memory_properties_; }

  bool validationEnabled() const { return validation_ != nullptr; }
  /// Validation warnings and errors seen so far (always 0 without validation).
  uint32_t validationMessageCount() const;
  std::string firstValidationMessage() const;

  /// Submits `info` to the compute queue, serialised (one SLAM thread owns the GPU, but tools may share a
  /// context). Once the device is lost — VK_ERROR_DEVICE_LOST from the driver, or simulateDeviceLoss() — every
  /// later submit returns VK_ERROR_DEVICE_LOST without reaching the driver, as a lost device does.
  VkResult submit(const VkSubmitInfo& info);
  /// The fault-injection seam (`vifusion run --inject device-lost@K`, vifusiond's `inject`): from now on the
  /// device behaves as lost. Work already submitted still completes, so waits and teardown stay safe.
  void simulateDeviceLoss() { device_lost_ = true; }
  bool deviceLost() const { return device_lost_; }

 private:
  GpuContext() = default;

  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_device_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queue_family_ = 0;
  GpuFeatures features_;
  VkPhysicalDeviceMemoryProperties memory_properties_{};
  std::unique_ptr<ValidationCounter> validation_;
  std::mutex queue_mutex_;
  std::atomic<bool> device_lost_{false};
};

}  // namespace vifusion::gpu
