#pragma once
// The file the writer appends to: POSIX write() in a loop (short writes, EINTR), fdatasync(), and a
// sticky failure that keeps what went wrong, where (path, byte offset, what was being written) and why
// (the errno text). No exceptions and no allocation except to compose that one failure message.

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace vifusion::mcap::detail {

class FileSink {
 public:
  FileSink() = default;
  FileSink(const FileSink&) = delete;
  FileSink& operator=(const FileSink&) = delete;
  ~FileSink();

  /// Creates or truncates `path` for writing. False (and failed()) when it cannot.
  bool open(const std::string& path);
  /// Appends all of `bytes`; `what` names them in a failure message ("Chunk record"). False once failed.
  bool write(std::span<const std::uint8_t> bytes, std::string_view what);
  /// fdatasync(): what was written is on the device. False once failed.
  bool sync();
  /// Closes the file (a close() error, e.g. a delayed write error on NFS, is a failure too).
  bool close();

  bool isOpen() const { return fd_ >= 0; }
  bool failed() const { return !error_.empty(); }
  const std::string& error() const { return error_; }
  const std::string& path() const { return path_; }
  /// Bytes written so far, partial writes included: the file's size while nothing failed.
  std::uint64_t offset() const { return offset_; }

 private:
  void fail(std::string_view action, int error_number);

  int fd_ = -1;
  std::string path_;
  std::string error_;
  std::uint64_t offset_ = 0;
};

}  // namespace vifusion::mcap::detail
