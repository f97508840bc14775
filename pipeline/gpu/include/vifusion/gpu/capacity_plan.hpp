#pragma once
// Every GPU buffer the process will ever use, declared before any memory is allocated.
// Stages add their buffers at start-up; MemoryArena turns the plan into one allocation per
// memory kind. An invalid plan (zero or oversized buffer, duplicate name, more than the device
// holds) is rejected with every problem listed, before anything is allocated.

#include <cstdint>
#include <string>
#include <vector>

#include "vifusion/gpu/gpu_context.hpp"

namespace vifusion::gpu {

/// How a buffer is used, which decides the memory kind it lives in.
enum class MemoryUse {
  DeviceLocal,  ///< written and read by kernels only: fastest memory for the GPU
  Upload,       ///< written by the host every frame, read by kernels (host-visible, coherent)
  Readback,     ///< written by kernels or copies, read by the host (host-visible, coherent, cached)
};

const char* memoryUseName(MemoryUse use);

/// Index of a buffer in its plan; valid for the MemoryArena built from that plan.
struct BufferId {
  uint32_t index = UINT32_MAX;
  bool valid() const { return index != UINT32_MAX; }
};

struct BufferRequest {
  std::string name;    ///< "preprocess.depth_raw", used in errors and reports
  uint64_t bytes = 0;  ///< size [bytes]
  MemoryUse use = MemoryUse::DeviceLocal;
};

class CapacityPlan {
 public:
  /// Declares a buffer. Never throws; problems are reported together by validate().
  BufferId addBuffer(std::string name, uint64_t bytes, MemoryUse use);

  const std::vector<BufferRequest>& buffers() const { return buffers_; }
  uint64_t totalBytes() const;

  /// Throws vifusion::Error listing every problem: empty plan, zero-sized or duplicate buffers,
  /// a buffer larger than the device's storage-buffer range, more bytes than a memory heap holds.
  void validate(const GpuFeatures& features, const VkPhysicalDeviceMemoryProperties& memory) const;

 private:
  std::vector<BufferRequest> buffers_;
};

}  // namespace vifusion::gpu
