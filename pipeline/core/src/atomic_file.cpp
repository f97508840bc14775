#include "vifusion/core/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <utility>

#include "vifusion/core/error.hpp"

namespace vifusion {
namespace {

std::filesystem::path directoryOf(const std::filesystem::path& path) {
  return path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
}

/// Filesystems without O_TMPFILE answer one of these (open(2)); anything else is a real failure.
bool lacksUnnamedFiles(int error_number) {
  return error_number == EOPNOTSUPP || error_number == EISDIR || error_number == EINVAL;
}

}  // namespace

AtomicFile::AtomicFile(std::filesystem::path path) : path_(std::move(path)), temporary_(path_.string() + ".tmp") {
  constexpr mode_t kMode = 0644;  // owner writes, all read (less the umask), as the map file always had
  fd_ = ::open(directoryOf(path_).c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, kMode);
  unnamed_ = fd_ >= 0;
  if (fd_ < 0 && lacksUnnamedFiles(errno)) {
    fd_ = ::open(temporary_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, kMode);
  }
  if (fd_ < 0) {
    const int error_number = errno;
    throw Error(path_.string() + ": cannot create a file in '" + directoryOf(path_).string() +
                "': " + std::strerror(error_number));
  }
}

AtomicFile::~AtomicFile() {
  if (fd_ >= 0) {
    ::close(fd_);
    if (!unnamed_) ::unlink(temporary_.c_str());
  }
}

void AtomicFile::removeTemporary() {
  if (fd_ >= 0) ::close(std::exchange(fd_, -1));
  if (!unnamed_) ::unlink(temporary_.c_str());
}

void AtomicFile::fail(const std::string& what, int error_number) {
  removeTemporary();
  throw Error(path_.string() + ": " + what + ": " + std::strerror(error_number) + " (the previous file is unchanged)");
}

void AtomicFile::write(std::span<const std::byte> bytes) { writeAt(size_, bytes); }

void AtomicFile::write(std::string_view text) { write(std::as_bytes(std::span(text.data(), text.size()))); }

void AtomicFile::writeAt(std::uint64_t offset, std::span<const std::byte> bytes) {
  if (fd_ < 0) throw Error(path_.string() + ": written after commit() or a failure");
  while (!bytes.empty()) {
    const ssize_t written = ::pwrite(fd_, bytes.data(), bytes.size(), static_cast<off_t>(offset));
    if (written < 0) {
      const int error_number = errno;
      if (error_number == EINTR) continue;
      fail("writing failed", error_number);
    }
    bytes = bytes.subspan(static_cast<std::size_t>(written));
    offset += static_cast<std::uint64_t>(written);
  }
  size_ = std::max(size_, offset);
}

void AtomicFile::commit() {
  if (fd_ < 0) throw Error(path_.string() + ": committed twice or after a failure");
  if (::fsync(fd_) != 0) fail("flushing to disk failed", errno);
  if (unnamed_) {
    // Linked in only now that it is complete. A "<path>.tmp" left by a crash between a link and its rename
    // is complete, but stale: it is replaced.
    const std::string self = "/proc/self/fd/" + std::to_string(fd_);
    int linked = ::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, temporary_.c_str(), AT_SYMLINK_FOLLOW);
    if (linked != 0 && errno == EEXIST && ::unlink(temporary_.c_str()) == 0) {
      linked = ::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, temporary_.c_str(), AT_SYMLINK_FOLLOW);
    }
    if (linked != 0) fail("linking the written file in as '" + temporary_.string() + "' failed", errno);
    unnamed_ = false;  // from here on there is a name to remove on failure
  }
  if (::close(std::exchange(fd_, -1)) != 0) fail("closing failed", errno);
  if (::rename(temporary_.c_str(), path_.c_str()) != 0)
    fail("renaming '" + temporary_.string() + "' over it failed", errno);
  // The rename is an entry in the directory: sync that too, so the new file survives a power loss.
  const std::filesystem::path directory = directoryOf(path_);
  const int directory_fd = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  const int error_number = directory_fd < 0 || ::fsync(directory_fd) != 0 ? errno : 0;
  if (directory_fd >= 0) ::close(directory_fd);
  if (error_number != 0) {
    throw Error(path_.string() + ": written, but syncing its directory '" + directory.string() +
                "' failed: " + std::strerror(error_number));
  }
}

void writeFileAtomically(const std::filesystem::path& path, std::string_view text) {
  AtomicFile file(path);
  file.write(text);
  file.commit();
}

void printFileAtomically(const std::filesystem::path& path, const std::function<void(std::FILE*)>& print) {
  char* data = nullptr;
  std::size_t size = 0;
  std::FILE* stream = ::open_memstream(&data, &size);
  if (stream == nullptr) throw Error(path.string() + ": cannot format it in memory: " + std::strerror(errno));
  try {
    print(stream);
  } catch (...) {
    std::fclose(stream);
    std::free(data);
    throw;
  }
  const bool printed = std::ferror(stream) == 0;
  if (std::fclose(stream) != 0 || !printed) {
    std::free(data);
    throw Error(path.string() + ": formatting it in memory failed");
  }
  std::unique_ptr<char, decltype(&std::free)> text(data, &std::free);
  writeFileAtomically(path, std::string_view(text.get(), size));
}

}  // namespace vifusion
