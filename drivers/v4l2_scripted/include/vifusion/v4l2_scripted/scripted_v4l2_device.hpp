#pragma once
// An in-memory V4L2 device behind the DeviceIo seam: one or more capture nodes (depth, colour, IR) with the
// streaming state machine of a vb2/uvcvideo driver, frames from a script on a ManualClock, and fault
// injection. It exists to drive vifusion::v4l2 through its real code paths without a camera, and is shaped
// to serve later as the device behind an LD_PRELOAD shim or inside the live source's end-to-end test.
//
// Rules enforced (each refusal that a correct client never triggers is a "rule violation": counted, with
// the last one described, so a test can prove that the client never does it):
//  - open: ENOENT for an unknown path or an unplugged node. fds start at kFirstFd (clear of real ones).
//  - VIDIOC_QUERYCAP; VIDIOC_S_FMT/G_FMT/TRY_FMT: an unknown fourcc falls back to formats[0]'s, the size to
//    the nearest offered, field NONE (as uvcvideo: it changes the request rather than failing); S_FMT is
//    EBUSY while buffers exist. VIDIOC_S_PARM/G_PARM: the nearest offered rate.
//  - VIDIOC_REQBUFS: MMAP only; the first fd to allocate owns the queue (others: EBUSY); EBUSY while
//    streaming or while any buffer is mapped; count clamped to [1, max_buffers]; count 0 frees.
//  - VIDIOC_QUERYBUF, mmap of exactly a buffer's offset (MAP_SHARED, ≤ its length), munmap of a mapping.
//  - VIDIOC_QBUF only of a buffer the client holds (not queued, not done): else EINVAL. VIDIOC_DQBUF: EAGAIN
//    with O_NONBLOCK when nothing is done (a blocking DQBUF advances the clock instead of sleeping); EINVAL
//    when not streaming. VIDIOC_STREAMON needs buffers; STREAMOFF returns every buffer to the client.
//  - poll: POLLIN|POLLRDNORM when a buffer is done; POLLERR when not streaming; POLLERR|POLLHUP once
//    unplugged; POLLNVAL for an unknown fd. A timeout advances the clock (see ManualClock).
//  - UVCIOC_CTRL_QUERY (GET_CUR/SET_CUR) on the node's control table: ENOENT unknown control, ENOBUFS wrong
//    size, EIO read-only (device answers, not violations). Unknown ioctls: ENOTTY.
//  - close of the queue owner stops streaming and frees the buffers (mappings stay valid until munmap).
// Injection: unplug() (or scheduleUnplug(t)): from then on every ioctl and mmap on that node's fds fails with
// ENODEV, poll reports POLLERR|POLLHUP, open fails with ENOENT; close and munmap still work. replug() (or
// scheduleReplug(t)): a fresh instance of every node (not streaming, controls as configured); old fds stay
// dead. Lost and error-flagged frames come from the FrameProducer.
//
// Thread-safe: one lock around everything, so depth and colour driver threads may share one device.
// Steady-state streaming (poll, DQBUF, QBUF) allocates nothing.

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "vifusion/v4l2/device_io.hpp"
#include "vifusion/v4l2/problem_text.hpp"
#include "vifusion/v4l2_scripted/manual_clock.hpp"
#include "vifusion/v4l2_scripted/scripted_node.hpp"

namespace vifusion::v4l2_scripted {

class NodeInstance;

class ScriptedV4l2Device final : public v4l2::DeviceIo {
 public:
  /// First file descriptor handed out: far above real descriptors, so a shim can tell them apart.
  static constexpr int kFirstFd = 1 << 28;

  explicit ScriptedV4l2Device(ManualClock& clock);
  ~ScriptedV4l2Device() override;
  ScriptedV4l2Device(const ScriptedV4l2Device&) = delete;
  ScriptedV4l2Device& operator=(const ScriptedV4l2Device&) = delete;

  /// Adds a node (before its first open). @throws vifusion::Error for a duplicate path, no formats, or no
  /// producer.
  void addNode(const ScriptedNodeConfig& config);

  // ---- injection ----
  void unplug();
  void replug();
  /// Unplug / replug when the manual clock reaches t_ns (processed in time order with the frames).
  void scheduleUnplug(std::int64_t t_ns);
  void scheduleReplug(std::int64_t t_ns);

  // ---- inspection ----
  ManualClock& clock() { return clock_; }
  bool plugged() const;
  std::int64_t ruleViolations() const;
  std::string lastViolation() const;
  int openFdCount() const;
  /// Mappings not yet unmapped, over all instances (old ones too).
  int liveMappingCount() const;
  /// The current instance's counters for `path`. @throws vifusion::Error for an unknown path.
  ScriptedNodeStats nodeStats(const std::string& path) const;
  /// The current value of an XU control, e.g. to check what a client wrote. Empty if there is none.
  std::vector<std::uint8_t> controlValue(const std::string& path, std::uint8_t unit, std::uint8_t selector) const;

  // ---- DeviceIo ----
  int open(const char* path, int flags) override;
  int close(int fd) override;
  int ioctl(int fd, unsigned long request, void* argument) override;
  void* mmap(void* address, std::size_t length, int protection, int flags, int fd, off_t offset) override;
  int munmap(void* address, std::size_t length) override;
  int poll(pollfd* fds, nfds_t count, int timeout_ms) override;

 private:
  struct OpenFile {
    int fd = -1;
    NodeInstance* node = nullptr;
    int flags = 0;
  };

  OpenFile* findFile(int fd);
  NodeInstance* currentInstance(const std::string& path) const;
  /// Delivers every scripted event up to the clock's now, in time order.
  void catchUp();
  /// The earliest scripted event (frame arrival, unplug, replug) still to come, if any.
  std::optional<std::int64_t> nextEventNs() const;
  void unplugLocked();
  void replugLocked();
  short pollEvents(int fd);
  /// Sets every revents; returns how many descriptors have events.
  int pollReady(pollfd* fds, nfds_t count);
  /// Counts and describes a rule violation; returns error_number (for "return violation(EINVAL, ...)").
  int violation(int error_number, const char* format, ...) __attribute__((format(printf, 3, 4)));

  ManualClock& clock_;
  mutable std::mutex mutex_;
  std::vector<std::unique_ptr<ScriptedNodeConfig>> configs_;  ///< stable addresses: instances refer to them
  std::vector<std::unique_ptr<NodeInstance>> instances_;      ///< every instance ever made (old fds point there)
  std::vector<NodeInstance*> current_;                        ///< per config: the instance plugged in now
  std::vector<OpenFile> files_;
  int next_fd_ = kFirstFd;
  bool plugged_ = true;
  std::optional<std::int64_t> unplug_at_ns_;
  std::optional<std::int64_t> replug_at_ns_;
  std::int64_t violations_ = 0;
  v4l2::ProblemText last_violation_;

  friend class NodeInstance;
};

}  // namespace vifusion::v4l2_scripted
