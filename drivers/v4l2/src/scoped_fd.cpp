#include "vifusion/v4l2/scoped_fd.hpp"

#include <cerrno>

#include "vifusion/v4l2/device_error.hpp"

namespace vifusion::v4l2 {

ScopedFd::ScopedFd(DeviceIo& io, const std::string& path, int flags) : io_(io), fd_(io.open(path.c_str(), flags)) {
  if (fd_ < 0) throw DeviceError(path + ": cannot open", errno);
}

ScopedFd::~ScopedFd() {
  if (fd_ >= 0) io_.close(fd_);
}

}  // namespace vifusion::v4l2
