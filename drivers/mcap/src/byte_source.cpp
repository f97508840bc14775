#include "vifusion/mcap/byte_source.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>
#include <utility>

#include "vifusion/core/error.hpp"

namespace vifusion::mcap {
namespace {

std::string errnoText(int error_number) { return std::system_category().message(error_number); }

void requireInRange(const std::string& name, std::uint64_t size, std::uint64_t offset, std::size_t bytes) {
  if (offset > size || bytes > size - offset) {
    throw Error(name + ": read of " + std::to_string(bytes) + " bytes at offset " + std::to_string(offset) +
                " is beyond the end (" + std::to_string(size) + " bytes)");
  }
}

}  // namespace

FileByteSource::FileByteSource(const std::string& path) : path_(path) {
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) throw Error(path + ": cannot open: " + errnoText(errno));
  struct stat status {};
  if (::fstat(fd_, &status) != 0) {
    const int error_number = errno;
    ::close(fd_);
    throw Error(path + ": cannot stat: " + errnoText(error_number));
  }
  if (!S_ISREG(status.st_mode)) {
    ::close(fd_);
    throw Error(path + ": not a regular file");
  }
  size_ = static_cast<std::uint64_t>(status.st_size);
}

FileByteSource::~FileByteSource() {
  if (fd_ >= 0) ::close(fd_);
}

void FileByteSource::read(std::uint64_t offset, std::span<std::uint8_t> out) const {
  requireInRange(path_, size_, offset, out.size());
  std::size_t done = 0;
  while (done < out.size()) {
    const ssize_t n = ::pread(fd_, out.data() + done, out.size() - done, static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      throw Error(path_ + ": read at offset " + std::to_string(offset + done) + " failed: " + errnoText(errno));
    }
    if (n == 0) {
      throw Error(path_ + ": the file shrank while being read (ends at " + std::to_string(offset + done) + ", was " +
                  std::to_string(size_) + " bytes)");
    }
    done += static_cast<std::size_t>(n);
  }
}

MemoryByteSource::MemoryByteSource(std::span<const std::uint8_t> bytes, std::string name)
    : bytes_(bytes), name_(std::move(name)) {}

void MemoryByteSource::read(std::uint64_t offset, std::span<std::uint8_t> out) const {
  requireInRange(name_, bytes_.size(), offset, out.size());
  if (!out.empty()) std::memcpy(out.data(), bytes_.data() + offset, out.size());
}

}  // namespace vifusion::mcap
