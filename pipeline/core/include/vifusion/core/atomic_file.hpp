#pragma once
// A file replaced atomically: a reader, or a restart after a crash, a SIGKILL or a power loss, sees either the
// previous complete file or the new complete one, never a truncated file. Until commit() the data goes to an
// unnamed file in the target's directory (O_TMPFILE), so even a process killed mid-write leaves nothing
// partial behind; commit() flushes it to disk (fsync), links it in as "<path>.tmp", renames that over `path`
// and syncs the directory. On a filesystem without O_TMPFILE the data is written to "<path>.tmp" directly.
// Every output a run or the service leaves (trajectory, states, frame log, report, PLY map, map file) is
// written through this.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <string_view>

namespace vifusion {

class AtomicFile {
 public:
  /// Creates the (unnamed) temporary file. Throws vifusion::Error naming `path` and the cause.
  explicit AtomicFile(std::filesystem::path path);
  /// Without commit() (an error, an exception in the caller): drops the temporary file and leaves `path` as
  /// it was.
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  const std::filesystem::path& path() const { return path_; }

  /// Appends `bytes`. Throws vifusion::Error naming `path` and the cause (disk full, file too large).
  void write(std::span<const std::byte> bytes);
  void write(std::string_view text);
  /// Overwrites bytes already written, at `offset` from the start (a header completed after its payload).
  void writeAt(std::uint64_t offset, std::span<const std::byte> bytes);
  /// fsync, link, rename over `path`, fsync of the directory. Throws vifusion::Error naming `path` and the
  /// step that failed; the temporary file is gone either way.
  void commit();

 private:
  [[noreturn]] void fail(const std::string& what, int error_number);
  void removeTemporary();

  std::filesystem::path path_;
  std::filesystem::path temporary_;  ///< "<path>.tmp": its name once linked in (or from the start, without O_TMPFILE)
  int fd_ = -1;
  bool unnamed_ = false;  ///< O_TMPFILE: nothing to unlink until commit() links it
  std::uint64_t size_ = 0;
};

/// Writes `text` to `path` through an AtomicFile.
void writeFileAtomically(const std::filesystem::path& path, std::string_view text);

/// Runs `print` on a stream in memory, then writes what it printed to `path` through an AtomicFile: for
/// writers that format with fprintf. Throws vifusion::Error naming `path`.
void printFileAtomically(const std::filesystem::path& path, const std::function<void(std::FILE*)>& print);

}  // namespace vifusion
