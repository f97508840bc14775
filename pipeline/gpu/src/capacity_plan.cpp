#include "vifusion/gpu/capacity_plan.hpp"

#include <algorithm>
#include <set>
#include <sstream>

#include "vifusion/core/error.hpp"

namespace vifusion::gpu {
namespace {

std::string mebibytes(uint64_t bytes) {
  std::ostringstream text;
  text.precision(1);
  text << std::fixed << static_cast<double>(bytes) / (1024.0 * 1024.0) << " MiB";
  return text.str();
}

VkMemoryPropertyFlags requiredFlags(MemoryUse use) {
  return use == MemoryUse::DeviceLocal ? 0
                                       : VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
}

/// The largest heap behind a memory type that satisfies `use`.
uint64_t largestHeapFor(MemoryUse use, const VkPhysicalDeviceMemoryProperties& memory) {
  uint64_t largest = 0;
  for (uint32_t i = 0; i < memory.memoryTypeCount; ++i) {
    const VkMemoryPropertyFlags required = requiredFlags(use);
    if ((memory.memoryTypes[i].propertyFlags & required) != required) continue;
    largest = std::max<uint64_t>(largest, memory.memoryHeaps[memory.memoryTypes[i].heapIndex].size);
  }
  return largest;
}

}  // namespace

const char* memoryUseName(MemoryUse use) {
  switch (use) {
    case MemoryUse::DeviceLocal: return "device-local";
    case MemoryUse::Upload: return "upload";
    case MemoryUse::Readback: return "readback";
  }
  return "?";
}

BufferId CapacityPlan::addBuffer(std::string name, uint64_t bytes, MemoryUse use) {
  buffers_.push_back({std::move(name), bytes, use});
  return BufferId{static_cast<uint32_t>(buffers_.size() - 1)};
}

uint64_t CapacityPlan::totalBytes() const {
  uint64_t total = 0;
  for (const BufferRequest& request : buffers_) total += request.bytes;
  return total;
}

void CapacityPlan::validate(const GpuFeatures& features, const VkPhysicalDeviceMemoryProperties& memory) const {
  std::vector<std::string> problems;
  if (buffers_.empty()) problems.push_back("the plan declares no buffers");
  std::set<std::string> names;
  uint64_t bytes_per_use[3] = {0, 0, 0};
  for (const BufferRequest& request : buffers_) {
    const std::string label = "buffer '" + request.name + "'";
    if (request.name.empty()) problems.push_back("a buffer has no name");
    if (!names.insert(request.name).second) problems.push_back(label + " is declared twice");
    if (request.bytes == 0) problems.push_back(label + " has size 0");
    if (request.bytes > features.max_storage_buffer_range_bytes) {
      problems.push_back(label + " needs " + mebibytes(request.bytes) + ", more than the device's storage-buffer range of " +
                         mebibytes(features.max_storage_buffer_range_bytes));
    }
    bytes_per_use[static_cast<int>(request.use)] += request.bytes;
  }
  for (MemoryUse use : {MemoryUse::DeviceLocal, MemoryUse::Upload, MemoryUse::Readback}) {
    const uint64_t needed = bytes_per_use[static_cast<int>(use)];
    const uint64_t heap = largestHeapFor(use, memory);
    if (needed > 0 && needed > heap) {
      problems.push_back(std::string(memoryUseName(use)) + " buffers need " + mebibytes(needed) +
                         " but the largest suitable memory heap holds " + mebibytes(heap));
    }
  }
  if (problems.empty()) return;
  std::string message = "invalid GPU capacity plan:";
  for (const std::string& problem : problems) message += "\n  - " + problem;
  throw Error(message);
}

}  // namespace vifusion::gpu
