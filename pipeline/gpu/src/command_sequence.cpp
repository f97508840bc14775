#include "vifusion/gpu/command_sequence.hpp"

#include "vifusion/core/error.hpp"
#include "vifusion/gpu/vulkan_check.hpp"

namespace vifusion::gpu {

void CommandRecorder::dispatch(const ComputeKernel& kernel, BindingSet set, std::array<uint32_t, 3> groups,
                               const void* push_data, uint32_t push_bytes) {
  if (push_bytes != kernel.spec().push_constant_bytes) {
    throw Error("shader '" + kernel.name() + "' expects " + std::to_string(kernel.spec().push_constant_bytes) +
                " bytes of push constants, got " + std::to_string(push_bytes));
  }
  vkCmdBindPipeline(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, kernel.pipeline());
  if (kernel.spec().storage_buffers > 0) {
    const VkDescriptorSet descriptor_set = kernel.descriptorSet(set);
    vkCmdBindDescriptorSets(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, kernel.layout(), 0, 1, &descriptor_set, 0, nullptr);
  }
  if (push_bytes > 0) {
    vkCmdPushConstants(cmd_, kernel.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes, push_data);
  }
  vkCmdDispatch(cmd_, groups[0], groups[1], groups[2]);
}

void CommandRecorder::computeBarrier() {
  VkMemoryBarrier barrier{};
  barrier.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  barrier.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT |
                          VK_ACCESS_TRANSFER_WRITE_BIT;
  const VkPipelineStageFlags stages = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
  vkCmdPipelineBarrier(cmd_, stages, stages, 0, 1, &barrier, 0, nullptr, 0, nullptr);
}

void CommandRecorder::resetQueries(VkQueryPool pool, uint32_t first, uint32_t count) {
  vkCmdResetQueryPool(cmd_, pool, first, count);
}

void CommandRecorder::writeTimestamp(VkQueryPool pool, uint32_t slot) {
  // Bottom of pipe: the value is taken once every earlier command has completed.
  vkCmdWriteTimestamp(cmd_, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool, slot);
}

void CommandRecorder::hostReadBarrier() {
  VkMemoryBarrier barrier{};
  barrier.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier, 0, nullptr, 0, nullptr);
}

void CommandRecorder::copyBuffer(const GpuBuffer& source, const GpuBuffer& destination, uint64_t bytes) {
  if (bytes > source.bytes || bytes > destination.bytes) {
    throw Error("copy of " + std::to_string(bytes) + " bytes from '" + source.name + "' to '" + destination.name +
                "' exceeds a buffer");
  }
  const VkBufferCopy region{0, 0, bytes};
  vkCmdCopyBuffer(cmd_, source.handle, destination.handle, 1, &region);
}

void CommandRecorder::fillBuffer(const GpuBuffer& destination, uint32_t value) {
  vkCmdFillBuffer(cmd_, destination.handle, 0, VK_WHOLE_SIZE, value);
}

std::unique_ptr<CommandSequence> CommandSequence::create(GpuContext& context, std::string name) {
  std::unique_ptr<CommandSequence> sequence(new CommandSequence(context, std::move(name)));
  CommandSequence& s = *sequence;
  const VkDevice device = context.device();
  const std::string where = "command sequence '" + s.name_ + "'";

  VkCommandPoolCreateInfo pool_info{};
  pool_info.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
  pool_info.queueFamilyIndex = context.queueFamily();
  checkVk(vkCreateCommandPool(device, &pool_info, nullptr, &s.pool_), "creating the command pool of " + where);

  VkCommandBufferAllocateInfo allocate_info{};
  allocate_info.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
  allocate_info.commandPool = s.pool_;
  allocate_info.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  allocate_info.commandBufferCount = 1;
  checkVk(vkAllocateCommandBuffers(device, &allocate_info, &s.command_buffer_),
          "allocating the command buffer of " + where);

  VkSemaphoreTypeCreateInfo type_info{};
  type_info.sType = VK_STRUCTURE_TYPE_SEMAPHORE_TYPE_CREATE_INFO;
  type_info.semaphoreType = VK_SEMAPHORE_TYPE_TIMELINE;
  type_info.initialValue = 0;
  VkSemaphoreCreateInfo semaphore_info{};
  semaphore_info.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO;
  semaphore_info.pNext = &type_info;
  checkVk(vkCreateSemaphore(device, &semaphore_info, nullptr, &s.timeline_), "creating the timeline of " + where);
  return sequence;
}

CommandSequence::~CommandSequence() {
  const VkDevice device = context_.device();
  if (timeline_ != VK_NULL_HANDLE) {
    if (last_submitted_ > 0) {
      const VkSemaphoreWaitInfo wait_info{
          VK_STRUCTURE_TYPE_SEMAPHORE_WAIT_INFO, nullptr, 0, 1, &timeline_, &last_submitted_};
      vkWaitSemaphores(device, &wait_info, UINT64_MAX);
    }
    vkDestroySemaphore(device, timeline_, nullptr);
  }
  if (pool_ != VK_NULL_HANDLE) vkDestroyCommandPool(device, pool_, nullptr);  // frees the command buffer
}

void CommandSequence::beginRecording() {
  if (last_submitted_ > 0) wait(last_submitted_);
  // Resetting the pool keeps its memory for the new recording (no allocation).
  checkVk(vkResetCommandPool(context_.device(), pool_, 0), "resetting command sequence '" + name_ + "'");
  VkCommandBufferBeginInfo begin{};
  begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
  checkVk(vkBeginCommandBuffer(command_buffer_, &begin), "recording command sequence '" + name_ + "'");
  recorded_ = false;
}

void CommandSequence::endRecording() {
  checkVk(vkEndCommandBuffer(command_buffer_), "finishing command sequence '" + name_ + "'");
  recorded_ = true;
}

uint64_t CommandSequence::submit() {
  if (!recorded_) throw Error("command sequence '" + name_ + "' was submitted before anything was recorded");
  if (last_submitted_ > 0) wait(last_submitted_);
  const uint64_t signal_value = last_submitted_ + 1;
  VkTimelineSemaphoreSubmitInfo timeline_info{};
  timeline_info.sType = VK_STRUCTURE_TYPE_TIMELINE_SEMAPHORE_SUBMIT_INFO;
  timeline_info.signalSemaphoreValueCount = 1;
  timeline_info.pSignalSemaphoreValues = &signal_value;
  VkSubmitInfo submit_info{};
  submit_info.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
  submit_info.pNext = &timeline_info;
  submit_info.commandBufferCount = 1;
  submit_info.pCommandBuffers = &command_buffer_;
  submit_info.signalSemaphoreCount = 1;
  submit_info.pSignalSemaphores = &timeline_;
  checkVk(context_.submit(submit_info), "submitting command sequence", name_);
  last_submitted_ = signal_value;
  return signal_value;
}

void CommandSequence::wait(uint64_t ticket, int64_t timeout_ns) {
  const VkSemaphoreWaitInfo wait_info{VK_STRUCTURE_TYPE_SEMAPHORE_WAIT_INFO, nullptr, 0, 1, &timeline_, &ticket};
  const VkResult result = vkWaitSemaphores(context_.device(), &wait_info, static_cast<uint64_t>(timeout_ns));
  if (result == VK_TIMEOUT) {
    throw Error("command sequence '" + name_ + "' did not finish within " + std::to_string(timeout_ns / 1'000'000) +
                " ms (GPU hung or overloaded)");
  }
  checkVk(result, "waiting for command sequence", name_);
}

bool CommandSequence::isComplete(uint64_t ticket) const {
  uint64_t value = 0;
  checkVk(vkGetSemaphoreCounterValue(context_.device(), timeline_, &value), "reading the timeline of", name_);
  return value >= ticket;
}

}  // namespace vifusion::gpu
