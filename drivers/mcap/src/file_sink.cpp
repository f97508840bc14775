#include "file_sink.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>

namespace vifusion::mcap::detail {
namespace {

constexpr mode_t kFileMode = 0644;  // rw-r--r--, before the umask: recordings are shared read-only

}  // namespace

FileSink::~FileSink() {
  if (fd_ >= 0) ::close(fd_);
}

bool FileSink::open(const std::string& path) {
  if (fd_ >= 0) ::close(fd_);
  path_ = path;
  error_.clear();
  offset_ = 0;
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, kFileMode);
  if (fd_ < 0) {
    fail("cannot create the file", errno);
    return false;
  }
  return true;
}

bool FileSink::write(std::span<const std::uint8_t> bytes, std::string_view what) {
  if (failed()) return false;
  if (fd_ < 0) {
    fail(std::string("cannot write ") + std::string(what) + ": the file is not open", EBADF);
    return false;
  }
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd_, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      // write() returning 0 for a non-empty request wrote nothing and would do so again: report it as a
      // full device rather than loop forever.
      fail("write of " + std::string(what) + " failed", n < 0 ? errno : ENOSPC);
      return false;
    }
    done += static_cast<std::size_t>(n);
    offset_ += static_cast<std::uint64_t>(n);
  }
  return true;
}

bool FileSink::sync() {
  if (failed()) return false;
  while (::fdatasync(fd_) != 0) {
    if (errno == EINTR) continue;
    fail("fdatasync failed", errno);
    return false;
  }
  return true;
}

bool FileSink::close() {
  if (fd_ < 0) return !failed();
  const int result = ::close(fd_);
  fd_ = -1;
  // close() must not be retried on EINTR (Linux has released the descriptor); its error still means
  // that an earlier write may not have reached the file.
  if (result != 0 && !failed()) fail("close failed", errno);
  return !failed();
}

void FileSink::fail(std::string_view action, int error_number) {
  if (failed()) return;  // the first failure is the cause; later ones follow from it
  error_ = path_ + ": " + std::string(action) + " at byte offset " + std::to_string(offset_) + ": " +
           std::system_category().message(error_number);
}

}  // namespace vifusion::mcap::detail
