#pragma once
// GPU timestamps at fixed points of recorded command sequences (Vulkan timestamp queries), for the
// per-frame budget: a sequence records reset(), then write(slot) between its stages; after its
// submission completed, read() gives the ticks and msBetween() the time between two slots. One pool
// of `slots` queries, created at start-up; nothing allocates per frame.
//
// Devices whose compute queue has no timestamps (GpuFeatures::timestamp_valid_bits = 0) give
// available() = false: the writes are not recorded and callers time on the CPU instead. A slot
// whose value is not available (not written in the last submission) reads as not valid.

#include <vulkan/vulkan.h>

#include <cstdint>
#include <memory>
#include <span>

#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/gpu/gpu_context.hpp"

namespace vifusion::gpu {

class TimestampPool {
 public:
  /// Throws vifusion::Error when `slots` is 0 or the pool cannot be created.
  TimestampPool(GpuContext& context, std::uint32_t slots);
  ~TimestampPool();
  TimestampPool(const TimestampPool&) = delete;
  TimestampPool& operator=(const TimestampPool&) = delete;

  bool available() const { return pool_ != VK_NULL_HANDLE; }
  std::uint32_t slots() const { return slots_; }

  /// Records the reset of slots [first, first + count) (before their writes, in the same sequence).
  void recordReset(CommandRecorder& recorder, std::uint32_t first, std::uint32_t count) const;
  /// Records a timestamp into `slot` once every command recorded before it has finished.
  void recordWrite(CommandRecorder& recorder, std::uint32_t slot) const;

  /// Reads slots [first, first + ticks.size()) of the last completed submission without waiting;
  /// false when the pool is unavailable or any of them holds no value.
  bool read(std::uint32_t first, std::span<std::uint64_t> ticks) const;
  /// Milliseconds from tick `from` to tick `to` of one read (valid bits and period applied).
  double msBetween(std::uint64_t from, std::uint64_t to) const;

 private:
  GpuContext& context_;
  std::uint32_t slots_ = 0;
  VkQueryPool pool_ = VK_NULL_HANDLE;
  std::uint64_t valid_mask_ = 0;
  double period_ns_ = 0.0;
};

}  // namespace vifusion::gpu
