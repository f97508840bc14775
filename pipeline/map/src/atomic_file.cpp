#include "atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <utility>

#include "vifusion/core/error.hpp"

namespace vifusion::map {

AtomicFile::AtomicFile(std::filesystem::path path) : path_(std::move(path)), temporary_(path_.string() + ".tmp") {
  fd_ = ::open(temporary_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd_ < 0) {
    const int error_number = errno;
    throw Error(path_.string() + ": cannot create the temporary file '" + temporary_.string() +
                "': " + std::strerror(error_number));
  }
}

AtomicFile::~AtomicFile() {
  if (fd_ >= 0) {
    ::close(fd_);
    ::unlink(temporary_.c_str());
  }
}

void AtomicFile::fail(const std::string& what, int error_number) {
  if (fd_ >= 0) ::close(std::exchange(fd_, -1));
  ::unlink(temporary_.c_str());
  throw Error(path_.string() + ": " + what + ": " + std::strerror(error_number) + " (the previous file is unchanged)");
}

void AtomicFile::write(std::span<const std::byte> bytes) {
  while (!bytes.empty()) {
    const ssize_t written = ::write(fd_, bytes.data(), bytes.size());
    if (written < 0) {
      const int error_number = errno;
      if (error_number == EINTR) continue;
      fail("writing '" + temporary_.string() + "' failed", error_number);
    }
    bytes = bytes.subspan(static_cast<std::size_t>(written));
  }
}

void AtomicFile::commit() {
  if (::fsync(fd_) != 0) {
    const int error_number = errno;
    fail("flushing '" + temporary_.string() + "' to disk failed", error_number);
  }
  if (::close(std::exchange(fd_, -1)) != 0) {
    const int error_number = errno;
    fail("closing '" + temporary_.string() + "' failed", error_number);
  }
  if (::rename(temporary_.c_str(), path_.c_str()) != 0) {
    const int error_number = errno;
    fail("renaming '" + temporary_.string() + "' over it failed", error_number);
  }
  // The rename is an entry in the directory: sync that too, so the new file survives a power loss.
  const std::filesystem::path directory = path_.has_parent_path() ? path_.parent_path() : ".";
  const int directory_fd = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  const int error_number = directory_fd < 0 || ::fsync(directory_fd) != 0 ? errno : 0;
  if (directory_fd >= 0) ::close(directory_fd);
  if (error_number != 0) {
    throw Error(path_.string() + ": written, but syncing its directory '" + directory.string() +
                "' failed: " + std::strerror(error_number));
  }
}

}  // namespace vifusion::map
