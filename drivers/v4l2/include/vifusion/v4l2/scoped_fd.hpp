#pragma once
// A device node opened through a DeviceIo for as long as this object lives, e.g. the IR node for the DS4
// extension-unit controls while only the depth and colour nodes stream.

#include <string>

#include "vifusion/v4l2/device_io.hpp"

namespace vifusion::v4l2 {

class ScopedFd {
 public:
  /// @throws DeviceError naming the path when open fails.
  ScopedFd(DeviceIo& io, const std::string& path, int flags);
  ~ScopedFd();
  ScopedFd(const ScopedFd&) = delete;
  ScopedFd& operator=(const ScopedFd&) = delete;

  int get() const { return fd_; }

 private:
  DeviceIo& io_;
  int fd_ = -1;
};

}  // namespace vifusion::v4l2
