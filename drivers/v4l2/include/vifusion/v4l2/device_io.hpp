#pragma once
// The thin syscall seam under the V4L2 driver: the six calls a V4L2 MMAP streaming client makes, with the
// signatures and semantics of the system calls themselves (success ≥ 0 or a pointer, failure −1 or
// MAP_FAILED with errno set). Everything in vifusion::v4l2 reaches the kernel only through a DeviceIo, so
// the real code paths can be driven by an in-memory device (vifusion::v4l2_scripted) in tests, and the
// same in-memory device can later sit behind an LD_PRELOAD shim or be injected into the live source.

#include <poll.h>
#include <sys/types.h>

#include <cstddef>

namespace vifusion::v4l2 {

class DeviceIo {
 public:
  virtual ~DeviceIo() = default;

  /// open(2): a file descriptor, or −1 with errno.
  virtual int open(const char* path, int flags) = 0;
  /// close(2): 0, or −1 with errno. The descriptor is released either way (Linux semantics).
  virtual int close(int fd) = 0;
  /// ioctl(2) with one pointer argument (every V4L2 and UVC ioctl): ≥ 0, or −1 with errno.
  virtual int ioctl(int fd, unsigned long request, void* argument) = 0;
  /// mmap(2): the mapping, or MAP_FAILED with errno.
  virtual void* mmap(void* address, std::size_t length, int protection, int flags, int fd, off_t offset) = 0;
  /// munmap(2): 0, or −1 with errno.
  virtual int munmap(void* address, std::size_t length) = 0;
  /// poll(2): number of descriptors with events, 0 on timeout, −1 with errno. timeout_ms < 0 waits forever.
  virtual int poll(pollfd* fds, nfds_t count, int timeout_ms) = 0;
};

/// The real system calls. Calls interrupted by a signal (EINTR) are repeated where that is correct:
/// open and ioctl are restarted; poll is restarted with what is left of its timeout on CLOCK_MONOTONIC;
/// close is not (Linux has released the descriptor already, and a retry could close a reused one).
class SystemDeviceIo final : public DeviceIo {
 public:
  int open(const char* path, int flags) override;
  int close(int fd) override;
  int ioctl(int fd, unsigned long request, void* argument) override;
  void* mmap(void* address, std::size_t length, int protection, int flags, int fd, off_t offset) override;
  int munmap(void* address, std::size_t length) override;
  int poll(pollfd* fds, nfds_t count, int timeout_ms) override;
};

}  // namespace vifusion::v4l2
