#include "vifusion/gpu/memory_arena.hpp"

#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <map>

#include "vifusion/core/error.hpp"
#include "vifusion/gpu/vulkan_check.hpp"

namespace vifusion::gpu {
namespace {

/// Asks the kernel for transparent huge pages over the whole pages inside [pointer, pointer + bytes): host memory
/// that a driver maps for us (lavapipe's, or system memory of a unified-memory GPU) is then committed in 2 MiB
/// pages, 512 times fewer faults than 4 KiB ones (the start-up cost: toolchains/README.md). Advisory only: where
/// the kernel has THP off or the range is not anonymous memory the call fails and nothing changes.
void adviseHugePages(void* pointer, std::size_t bytes) {
  const auto page = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
  const auto begin = (reinterpret_cast<std::uintptr_t>(pointer) + page - 1) / page * page;
  const auto end = (reinterpret_cast<std::uintptr_t>(pointer) + bytes) / page * page;
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
}

struct MemoryPreference {
  VkMemoryPropertyFlags required;
  VkMemoryPropertyFlags preferred;
};

// Uploads prefer device-local host-visible memory (UMA SBCs, resizable BAR) so kernels read them
// at full speed; readbacks prefer cached memory because uncached CPU reads are very slow.
MemoryPreference preferenceFor(MemoryUse use) {
  constexpr VkMemoryPropertyFlags kHostCoherent =
      VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  switch (use) {
    case MemoryUse::DeviceLocal:
      return {VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0};
    case MemoryUse::Upload:
      return {kHostCoherent, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT};
    case MemoryUse::Readback:
      return {kHostCoherent, VK_MEMORY_PROPERTY_HOST_CACHED_BIT};
  }
  return {0, 0};
}

/// Picks the memory type for `use` among `allowed_types` (a memoryTypeBits mask).
uint32_t chooseMemoryType(const VkPhysicalDeviceMemoryProperties& memory, uint32_t allowed_types, MemoryUse use) {
  const MemoryPreference preference = preferenceFor(use);
  int best = -1;
  for (uint32_t i = 0; i < memory.memoryTypeCount; ++i) {
    if ((allowed_types & (1u << i)) == 0) continue;
    const VkMemoryPropertyFlags flags = memory.memoryTypes[i].propertyFlags;
    if ((flags & preference.required) != preference.required) continue;
    if ((flags & preference.preferred) == preference.preferred) return i;
    if (best < 0) best = static_cast<int>(i);
  }
  // Device-local is a preference for speed, not a must: a device without it still runs.
  if (best < 0 && use == MemoryUse::DeviceLocal) {
    for (uint32_t i = 0; i < memory.memoryTypeCount; ++i) {
      if ((allowed_types & (1u << i)) != 0) return i;
    }
  }
  if (best < 0) throw Error(std::string("no memory type suitable for ") + memoryUseName(use) + " buffers");
  return static_cast<uint32_t>(best);
}

uint64_t alignUp(uint64_t value, uint64_t alignment) { return (value + alignment - 1) / alignment * alignment; }

}  // namespace

std::unique_ptr<MemoryArena> MemoryArena::create(const GpuContext& context, const CapacityPlan& plan) {
  plan.validate(context.features(), context.memoryProperties());
  std::unique_ptr<MemoryArena> arena(new MemoryArena(context.device()));
  const VkDevice device = context.device();

  // Create every buffer first to learn its size, alignment and allowed memory types.
  struct Placement {
    VkMemoryRequirements requirements{};
    uint32_t memory_type = 0;
    uint64_t offset = 0;
  };
  std::vector<Placement> placements(plan.buffers().size());
  arena->buffers_.reserve(plan.buffers().size());
  for (std::size_t i = 0; i < plan.buffers().size(); ++i) {
    const BufferRequest& request = plan.buffers()[i];
    VkBufferCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
    info.size = request.bytes;
    info.usage =
        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    GpuBuffer buffer;
    buffer.bytes = request.bytes;
    buffer.name = request.name;
    checkVk(vkCreateBuffer(device, &info, nullptr, &buffer.handle), "creating buffer '" + request.name + "'");
    arena->buffers_.push_back(std::move(buffer));
    vkGetBufferMemoryRequirements(device, arena->buffers_.back().handle, &placements[i].requirements);
    placements[i].memory_type =
        chooseMemoryType(context.memoryProperties(), placements[i].requirements.memoryTypeBits, request.use);
  }

  // One allocation per memory type in use; buffers are placed back to back with their alignment.
  std::map<uint32_t, uint64_t> bytes_per_type;
  for (Placement& placement : placements) {
    uint64_t& end = bytes_per_type[placement.memory_type];
    placement.offset = alignUp(end, placement.requirements.alignment);
    end = placement.offset + placement.requirements.size;
  }
  std::map<uint32_t, std::size_t> block_of_type;
  for (const auto& [memory_type, bytes] : bytes_per_type) {
    VkMemoryAllocateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
    info.allocationSize = bytes;
    info.memoryTypeIndex = memory_type;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    const VkMemoryPropertyFlags flags = context.memoryProperties().memoryTypes[memory_type].propertyFlags;
    checkVk(vkAllocateMemory(device, &info, nullptr, &memory), "allocating the GPU arena for memory type " +
                                                                   std::to_string(memory_type) + " (" +
                                                                   std::to_string(bytes) + " bytes)");
    arena->memories_.push_back(memory);
    block_of_type[memory_type] = arena->blocks_.size();
    arena->blocks_.push_back({memory_type, flags, bytes, 0});
  }

  std::vector<std::byte*> mapped(arena->memories_.size(), nullptr);
  for (std::size_t block = 0; block < arena->blocks_.size(); ++block) {
    if ((arena->blocks_[block].flags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) == 0) continue;
    void* pointer = nullptr;
    checkVk(vkMapMemory(device, arena->memories_[block], 0, VK_WHOLE_SIZE, 0, &pointer), "mapping the GPU arena");
    mapped[block] = static_cast<std::byte*>(pointer);
    // Committed now, not page by page as the map fills: a machine short of memory fails here at start rather than
    // hours into a run, and the process's resident memory is flat from the first frame (system memory of a
    // unified-memory GPU, or of lavapipe, is otherwise resident only once touched). Zeros also give every buffer
    // a defined first content.
    adviseHugePages(pointer, arena->blocks_[block].bytes);
    std::memset(pointer, 0, arena->blocks_[block].bytes);
  }
  for (std::size_t i = 0; i < placements.size(); ++i) {
    const std::size_t block = block_of_type[placements[i].memory_type];
    GpuBuffer& buffer = arena->buffers_[i];
    checkVk(vkBindBufferMemory(device, buffer.handle, arena->memories_[block], placements[i].offset),
            "binding buffer '" + buffer.name + "'");
    if (mapped[block] != nullptr) buffer.mapped = mapped[block] + placements[i].offset;
    ++arena->blocks_[block].buffer_count;
  }
  return arena;
}

MemoryArena::~MemoryArena() {
  for (GpuBuffer& buffer : buffers_) vkDestroyBuffer(device_, buffer.handle, nullptr);
  for (VkDeviceMemory memory : memories_) vkFreeMemory(device_, memory, nullptr);
}

const GpuBuffer& MemoryArena::buffer(BufferId id) const {
  if (!id.valid() || id.index >= buffers_.size()) {
    throw Error("buffer id " + std::to_string(id.index) + " is not in this arena");
  }
  return buffers_[id.index];
}

uint64_t MemoryArena::allocatedBytes() const {
  uint64_t total = 0;
  for (const ArenaBlock& block : blocks_) total += block.bytes;
  return total;
}

}  // namespace vifusion::gpu
