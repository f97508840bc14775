#pragma once
// A command buffer recorded once and submitted many times (Kompute's Sequence), with a timeline
// semaphore whose value counts completed submissions. Per-frame values that change belong in
// mapped buffers, not in re-recorded push constants.

#include <vulkan/vulkan.h>

#include <array>
#include <cstdint>
#include <memory>
#include <string>

#include "vifusion/gpu/compute_kernel.hpp"
#include "vifusion/gpu/gpu_context.hpp"
#include "vifusion/gpu/memory_arena.hpp"

namespace vifusion::gpu {

/// Records into one command buffer; only valid inside CommandSequence::record().
class CommandRecorder {
 public:
  explicit CommandRecorder(VkCommandBuffer command_buffer) : cmd_(command_buffer) {}

  /// Binds `kernel` with binding set `set`, pushes `push_bytes` of constants and dispatches.
  void dispatch(const ComputeKernel& kernel, BindingSet set, std::array<uint32_t, 3> groups,
                const void* push_data = nullptr, uint32_t push_bytes = 0);
  template <typename Push>
  void dispatch(const ComputeKernel& kernel, BindingSet set, std::array<uint32_t, 3> groups, const Push& push) {
    dispatch(kernel, set, groups, &push, static_cast<uint32_t>(sizeof(Push)));
  }

  /// Makes earlier shader and transfer writes visible to later shaders and transfers.
  void computeBarrier();
  /// Makes earlier shader and transfer writes visible to the host after the submission completes.
  void hostReadBarrier();
  void copyBuffer(const GpuBuffer& source, const GpuBuffer& destination, uint64_t bytes);
  void fillBuffer(const GpuBuffer& destination, uint32_t value);
  /// Query commands for TimestampPool (timestamp_pool.hpp).
  void resetQueries(VkQueryPool pool, uint32_t first, uint32_t count);
  void writeTimestamp(VkQueryPool pool, uint32_t slot);

 private:
  VkCommandBuffer cmd_;
};

class CommandSequence {
 public:
  static std::unique_ptr<CommandSequence> create(GpuContext& context, std::string name);
  ~CommandSequence();
  CommandSequence(const CommandSequence&) = delete;
  CommandSequence& operator=(const CommandSequence&) = delete;

  /// Replaces the recorded commands (start-up, or when bindings change). Waits for the GPU first.
  template <typename Fn>
  void record(Fn&& fn) {
    beginRecording();
    CommandRecorder recorder(command_buffer_);
    fn(recorder);
    endRecording();
  }

  /// Submits the recorded commands; returns the timeline value that marks their completion.
  /// Waits for this sequence's previous submission first (a command buffer runs once at a time).
  uint64_t submit();
  /// Waits until submission `ticket` completed. Throws vifusion::Error naming the sequence on
  /// timeout or device loss, so a hung GPU becomes a reportable fault, not a silent stall. The default
  /// is generous: on lavapipe sharing 2 oversubscribed cores one map update of a 640×480 run took
  /// longer than the former 5 s and killed a healthy run; a live service's liveness is the systemd
  /// watchdog's job, which sees frames stop long before this fires.
  void wait(uint64_t ticket, int64_t timeout_ns = 60'000'000'000);
  void run() { wait(submit()); }
  bool isComplete(uint64_t ticket) const;

  const std::string& name() const { return name_; }

 private:
  CommandSequence(GpuContext& context, std::string name) : context_(context), name_(std::move(name)) {}
  void beginRecording();
  void endRecording();

  GpuContext& context_;
  std::string name_;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkCommandBuffer command_buffer_ = VK_NULL_HANDLE;
  VkSemaphore timeline_ = VK_NULL_HANDLE;
  uint64_t last_submitted_ = 0;
  bool recorded_ = false;
};

}  // namespace vifusion::gpu
