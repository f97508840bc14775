#pragma once
// A file replaced atomically: written under "<path>.tmp" in the same directory, flushed to disk
// (fsync), then renamed over `path` and the directory synced. A reader, or a restart after a
// crash or power loss, sees either the previous complete file or the new complete one, never a
// truncated file. Private to pipeline/map (the PLY export); a candidate for core if other
// writers (trajectory.txt, report.json) want the same guarantee.

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>

namespace vifusion::map {

class AtomicFile {
 public:
  /// Creates (or truncates) the temporary file. Throws vifusion::Error naming `path` and the cause.
  explicit AtomicFile(std::filesystem::path path);
  /// Without commit() (an error, an exception in the caller): removes the temporary file and
  /// leaves `path` as it was.
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  /// Appends `bytes`. Throws vifusion::Error naming `path` and the cause (disk full, file too large).
  void write(std::span<const std::byte> bytes);
  /// fsync, close, rename over `path`, fsync of the directory. Throws vifusion::Error naming
  /// `path` and the step that failed; the temporary file is gone either way.
  void commit();

 private:
  [[noreturn]] void fail(const std::string& what, int error_number);

  std::filesystem::path path_;
  std::filesystem::path temporary_;
  int fd_ = -1;
};

}  // namespace vifusion::map
