#pragma once
// Writes a map file (map_file_format.hpp) as a stream: sections one after the other, each payload appended
// field by field or chunk by chunk through one buffer, so a map larger than any host copy of it is written
// with the buffer's memory only. The file appears at its path only when commit() succeeds (core/atomic_file.hpp:
// an unnamed file, synced, linked in and renamed over the path), so a crash, a SIGKILL, a full disk or an
// exception leaves the previous file at the path untouched and nothing partial beside it.
//
// Errors throw vifusion::Error naming the path, the section being written and the system's reason.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "vifusion/core/atomic_file.hpp"
#include "vifusion/core/crc32.hpp"
#include "vifusion/mapfile/map_file_format.hpp"

namespace vifusion::mapfile {

class MapFileWriter {
 public:
  /// Bytes gathered before each write(2): large enough that a write costs little per byte.
  static constexpr std::size_t kDefaultBufferBytes = std::size_t{1} << 20;

  /// Creates the unwritten file and writes the file header. @throws vifusion::Error when it cannot.
  explicit MapFileWriter(std::string path, std::size_t buffer_bytes = kDefaultBufferBytes);
  ~MapFileWriter();
  MapFileWriter(const MapFileWriter&) = delete;
  MapFileWriter& operator=(const MapFileWriter&) = delete;

  /// Starts the next section; sections must come in MapSection order, each once (kEnd is commit()'s).
  void beginSection(MapSection section);
  void putU8(std::uint8_t value);
  void putU32(std::uint32_t value);
  void putI32(std::int32_t value);
  void putU64(std::uint64_t value);
  void putI64(std::int64_t value);
  void putF32(float value);
  void putF64(double value);
  void putBytes(std::span<const std::uint8_t> bytes);
  /// Floats bit for bit (a NaN's payload and the colour bits a surfel keeps in a float survive).
  void putF32s(std::span<const float> values);
  /// Ends the section: its size and checksum go into its header.
  void endSection();

  /// Writes the end section, syncs, and renames the file into place. @returns the file's size [bytes].
  std::uint64_t commit();

  const std::string& path() const { return path_; }

 private:
  void reserve(std::size_t bytes);  ///< makes room for `bytes` more in the buffer, flushing it if needed
  void flush();
  void writeAt(std::uint64_t offset, std::span<const std::uint8_t> bytes);
  [[noreturn]] void fail(const std::string& what) const;

  std::string path_;
  AtomicFile file_;
  std::vector<std::uint8_t> buffer_;  ///< capacity fixed at construction
  std::uint64_t offset_ = 0;          ///< bytes written to the file so far (the buffer's start)
  int next_section_ = 0;              ///< MapSection expected next
  bool in_section_ = false;
  std::uint64_t section_header_offset_ = 0;
  std::uint64_t section_bytes_ = 0;
  Crc32 section_crc_;  ///< of the section's payload flushed so far
};

}  // namespace vifusion::mapfile
