#include "vifusion/gpu/timestamp_pool.hpp"

#include <string>

#include "vifusion/core/error.hpp"
#include "vifusion/gpu/vulkan_check.hpp"

namespace vifusion::gpu {

TimestampPool::TimestampPool(GpuContext& context, std::uint32_t slots) : context_(context), slots_(slots) {
  if (slots == 0) throw Error("timestamp pool: needs at least one slot");
  const GpuFeatures& features = context.features();
  if (features.timestamp_valid_bits == 0 || !(features.timestamp_period_ns > 0.0)) return;
  VkQueryPoolCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO;
  info.queryType = VK_QUERY_TYPE_TIMESTAMP;
  info.queryCount = slots;
  checkVk(vkCreateQueryPool(context.device(), &info, nullptr, &pool_), "vkCreateQueryPool (timestamps)");
  valid_mask_ =
      features.timestamp_valid_bits >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << features.timestamp_valid_bits) - 1;
  period_ns_ = features.timestamp_period_ns;
}

TimestampPool::~TimestampPool() {
  if (pool_ != VK_NULL_HANDLE) vkDestroyQueryPool(context_.device(), pool_, nullptr);
}

void TimestampPool::recordReset(CommandRecorder& recorder, std::uint32_t first, std::uint32_t count) const {
  if (first + count > slots_) {
    throw Error("timestamp pool: slots " + std::to_string(first) + ".." + std::to_string(first + count) +
                " beyond its " + std::to_string(slots_));
  }
  if (available()) recorder.resetQueries(pool_, first, count);
}

void TimestampPool::recordWrite(CommandRecorder& recorder, std::uint32_t slot) const {
  if (slot >= slots_) {
    throw Error("timestamp pool: slot " + std::to_string(slot) + " beyond its " + std::to_string(slots_));
  }
  if (available()) recorder.writeTimestamp(pool_, slot);
}

bool TimestampPool::read(std::uint32_t first, std::span<std::uint64_t> ticks) const {
  if (!available() || ticks.empty() || first + ticks.size() > slots_) return false;
  // Value and availability word per query; at most a handful of slots per read.
  constexpr std::size_t kMaxRead = 16;
  if (ticks.size() > kMaxRead) return false;
  std::uint64_t words[2 * kMaxRead];
  const VkResult result =
      vkGetQueryPoolResults(context_.device(), pool_, first, static_cast<std::uint32_t>(ticks.size()),
                            sizeof(std::uint64_t) * 2 * ticks.size(), words, 2 * sizeof(std::uint64_t),
                            VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WITH_AVAILABILITY_BIT);
  if (result != VK_SUCCESS && result != VK_NOT_READY) return false;
  for (std::size_t i = 0; i < ticks.size(); ++i) {
    if (words[2 * i + 1] == 0) return false;
    ticks[i] = words[2 * i] & valid_mask_;
  }
  return true;
}

double TimestampPool::msBetween(std::uint64_t from, std::uint64_t to) const {
  const std::uint64_t ticks = (to - from) & valid_mask_;  // wraps within the valid bits
  return static_cast<double>(ticks) * period_ns_ * 1e-6;
}

}  // namespace vifusion::gpu
