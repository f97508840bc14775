#include <fcntl.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>

#include "vifusion/core/time.hpp"
#include "vifusion/v4l2/device_io.hpp"

namespace vifusion::v4l2 {

int SystemDeviceIo::open(const char* path, int flags) {
  int fd = -1;
  do {
    fd = ::open(path, flags | O_CLOEXEC);
  } while (fd < 0 && errno == EINTR);
  return fd;
}

int SystemDeviceIo::close(int fd) { return ::close(fd); }

int SystemDeviceIo::ioctl(int fd, unsigned long request, void* argument) {
  int result = -1;
  do {
    result = ::ioctl(fd, request, argument);
  } while (result < 0 && errno == EINTR);
  return result;
}

void* SystemDeviceIo::mmap(void* address, std::size_t length, int protection, int flags, int fd, off_t offset) {
  return ::mmap(address, length, protection, flags, fd, offset);
}

int SystemDeviceIo::munmap(void* address, std::size_t length) { return ::munmap(address, length); }

int SystemDeviceIo::poll(pollfd* fds, nfds_t count, int timeout_ms) {
  const std::int64_t deadline_ns = monotonicNowNs() + static_cast<std::int64_t>(timeout_ms) * kNsPerMillisecond;
  int wait_ms = timeout_ms;
  while (true) {
    const int result = ::poll(fds, count, wait_ms);
    if (result >= 0 || errno != EINTR) return result;
    if (timeout_ms < 0) continue;  // waiting forever: just wait again
    const std::int64_t left_ns = deadline_ns - monotonicNowNs();
    if (left_ns <= 0) return 0;
    // Round up so a sub-millisecond remainder still waits instead of spinning.
    wait_ms = static_cast<int>((left_ns + kNsPerMillisecond - 1) / kNsPerMillisecond);
  }
}

}  // namespace vifusion::v4l2
