#pragma once
// One plugged-in instance of a scripted node: its format, its vb2-like buffer queue and its controls.
// Private to vifusion::v4l2_scripted; ScriptedV4l2Device owns the lock, the clock and the fd table, and calls
// in here with the lock held. Handlers return 0 or an errno value.

#include <linux/videodev2.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "vifusion/v4l2_scripted/scripted_node.hpp"

namespace vifusion::v4l2_scripted {

class ScriptedV4l2Device;

/// A fixed-capacity FIFO of buffer indices (sized at REQBUFS, so streaming never allocates).
class IndexFifo {
 public:
  void reset(int capacity) {
    slots_.assign(static_cast<std::size_t>(capacity), -1);
    head_ = 0;
    size_ = 0;
  }
  bool empty() const { return size_ == 0; }
  int size() const { return size_; }
  void push(int index) {
    slots_[static_cast<std::size_t>((head_ + size_) % capacity())] = index;
    ++size_;
  }
  int front() const { return slots_[static_cast<std::size_t>(head_)]; }
  int pop() {
    const int index = slots_[static_cast<std::size_t>(head_)];
    head_ = (head_ + 1) % capacity();
    --size_;
    return index;
  }
  void clear() {
    head_ = 0;
    size_ = 0;
  }

 private:
  int capacity() const { return static_cast<int>(slots_.size()); }
  std::vector<int> slots_;
  int head_ = 0;
  int size_ = 0;
};

class NodeInstance {
 public:
  NodeInstance(const ScriptedNodeConfig& config, ScriptedV4l2Device& device);

  const ScriptedNodeConfig& config() const { return config_; }
  bool gone() const { return gone_; }
  void markGone() { gone_ = true; }

  int ioctl(int fd, int file_flags, unsigned long request, void* argument);
  /// 0 and *mapping set, or an errno value.
  int mmap(std::size_t length, int protection, int flags, off_t offset, void** mapping);
  /// True when `address` was a live mapping of this instance (now unmapped).
  bool unmap(void* address);
  void closeFile(int fd);
  short pollEvents() const;

  /// The next arrival while streaming with frames left in the script.
  std::optional<std::int64_t> nextArrivalNs() const;
  /// Handles that arrival (fill a queued buffer, or drop the frame).
  void deliverArrival();

  ScriptedNodeStats stats() const;
  int liveMappings() const;
  const ScriptedControl* control(std::uint8_t unit, std::uint8_t selector) const;

 private:
  ScriptedControl* findControl(std::uint8_t unit, std::uint8_t selector);
  enum class Owner { kClient, kQueued, kDone };
  struct Storage {
    std::vector<std::uint8_t> bytes;
    int maps = 0;
  };
  struct Buffer {
    std::unique_ptr<Storage> storage;
    std::uint32_t offset = 0;
    Owner owner = Owner::kClient;
    std::uint32_t sequence = 0;
    std::int64_t t_stamp_ns = 0;
    std::uint32_t flags = 0;
    std::uint32_t bytes_used = 0;
  };

  int queryCapability(v4l2_capability& capability) const;
  int setFormat(v4l2_format& format, bool apply);
  int getFormat(v4l2_format& format) const;
  int setParameters(v4l2_streamparm& parameters);
  int getParameters(v4l2_streamparm& parameters) const;
  int requestBuffers(int fd, v4l2_requestbuffers& request);
  int queryBuffer(v4l2_buffer& buffer) const;
  int queueBuffer(int fd, v4l2_buffer& buffer);
  int dequeueBuffer(int fd, int file_flags, v4l2_buffer& buffer);
  int streamOn(int fd, const int* type);
  int streamOff(int fd, const int* type);
  int controlQuery(void* argument);

  int checkBufferRequest(const v4l2_buffer& buffer, const char* call) const;
  int checkOwner(int fd, const char* call) const;
  void describe(v4l2_buffer& buffer, int index) const;
  void stopStreaming();
  void freeBuffers();
  std::int64_t periodNs() const;
  const ScriptedFormat* findFormat(std::uint32_t fourcc, int width_px, int height_px) const;

  const ScriptedNodeConfig& config_;
  ScriptedV4l2Device& device_;
  bool gone_ = false;
  v4l2_pix_format format_{};
  int fps_ = 0;
  std::vector<int> format_rates_;
  std::vector<ScriptedControl> controls_;
  std::vector<Buffer> buffers_;
  std::vector<std::unique_ptr<Storage>> orphans_;  ///< freed while mapped; alive until munmap
  int queue_owner_fd_ = -1;
  bool streaming_ = false;
  IndexFifo queued_;
  IndexFifo done_;
  std::int64_t next_frame_index_ = 0;
  std::uint32_t next_sequence_ = 0;
  ScriptedNodeStats stats_;
};

}  // namespace vifusion::v4l2_scripted
