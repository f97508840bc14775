#pragma once
// All GPU memory of the process: one vkAllocateMemory per memory kind, sized from the capacity
// plan at start-up and sub-allocated to every buffer. Host-visible memory stays mapped for the
// arena's lifetime, so per-frame uploads and readbacks are plain memcpy; it is zeroed at creation,
// which commits it (resident from the start, never growing as the map fills).

#include <vulkan/vulkan.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "vifusion/gpu/capacity_plan.hpp"
#include "vifusion/gpu/gpu_context.hpp"

namespace vifusion::gpu {

/// A buffer inside the arena. `mapped` is null unless its memory is host-visible.
struct GpuBuffer {
  VkBuffer handle = VK_NULL_HANDLE;
  uint64_t bytes = 0;
  std::byte* mapped = nullptr;
  std::string name;

  template <typename T>
  std::span<T> hostSpan() const {
    return {reinterpret_cast<T*>(mapped), static_cast<std::size_t>(bytes / sizeof(T))};
  }
};

/// One memory allocation shared by all buffers of one memory kind.
struct ArenaBlock {
  uint32_t memory_type = 0;
  VkMemoryPropertyFlags flags = 0;
  uint64_t bytes = 0;  ///< allocated size, including alignment padding
  uint32_t buffer_count = 0;
};

class MemoryArena {
 public:
  /// Validates the plan, creates every buffer and binds it into one allocation per memory kind.
  static std::unique_ptr<MemoryArena> create(const GpuContext& context, const CapacityPlan& plan);
  ~MemoryArena();
  MemoryArena(const MemoryArena&) = delete;
  MemoryArena& operator=(const MemoryArena&) = delete;

  const GpuBuffer& buffer(BufferId id) const;
  const std::vector<ArenaBlock>& blocks() const { return blocks_; }
  uint64_t allocatedBytes() const;

 private:
  explicit MemoryArena(VkDevice device) : device_(device) {}

  VkDevice device_;
  std::vector<GpuBuffer> buffers_;
  std::vector<VkDeviceMemory> memories_;
  std::vector<ArenaBlock> blocks_;
};

}  // namespace vifusion::gpu
