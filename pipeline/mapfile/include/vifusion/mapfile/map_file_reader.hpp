#pragma once
// Reads a map file (map_file_format.hpp) as a stream, section by section in file order, through one buffer:
// a map larger than the reader's memory loads chunk by chunk. A section small enough for the buffer is
// read whole and its checksum checked before any field is decoded; a larger one (surfels, keyframes) is
// checked when endSection() has read it all, so its consumer must treat what it took as provisional until
// then (the loader uploads, and discards the map on an error).
//
// Every error throws vifusion::Error naming the file, the section and what is wrong with it: not a map file,
// a newer format version, a corrupt header, a checksum mismatch, a section cut short, a section missing or out
// of order, a payload with more or fewer bytes than its fields.

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "vifusion/core/crc32.hpp"
#include "vifusion/mapfile/map_file_format.hpp"

namespace vifusion::mapfile {

class MapFileReader {
 public:
  static constexpr std::size_t kDefaultBufferBytes = std::size_t{1} << 20;

  /// Opens the file and checks its header. @throws vifusion::Error as above.
  explicit MapFileReader(std::string path, std::size_t buffer_bytes = kDefaultBufferBytes);
  ~MapFileReader();
  MapFileReader(const MapFileReader&) = delete;
  MapFileReader& operator=(const MapFileReader&) = delete;

  std::uint32_t formatVersion() const { return version_; }
  std::uint64_t fileBytes() const { return file_bytes_; }
  const std::string& path() const { return path_; }

  /// Reads the next section's header; it must be `expected` (sections come in MapSection order).
  /// @returns its payload size [bytes]
  std::uint64_t beginSection(MapSection expected);
  std::uint8_t getU8();
  std::uint32_t getU32();
  std::int32_t getI32();
  std::uint64_t getU64();
  std::int64_t getI64();
  float getF32();
  double getF64();
  void getBytes(std::span<std::uint8_t> out);
  void getF32s(std::span<float> out);
  /// The payload size of a section begun so far [bytes]; 0 for one not reached yet.
  std::uint64_t sectionBytes(MapSection section) const { return payload_bytes_[static_cast<std::size_t>(section)]; }
  /// Payload bytes of the current section not read yet.
  std::uint64_t remaining() const { return section_bytes_ - section_read_; }
  /// Ends the section: every payload byte must have been read, and the checksum must match.
  void endSection();
  /// Reads the current section's remaining payload without decoding it, then ends it.
  void skipRest();
  /// After the last section: reads the end section and checks nothing follows it.
  void finish();

  /// Throws vifusion::Error "map file <path>: section '<current>': <what>" (for decoders' value checks).
  [[noreturn]] void fail(const std::string& what) const;

 private:
  /// Makes `bytes` (≤ the buffer's capacity) of the current payload available at buffer_[position_].
  void need(std::size_t bytes);
  /// Reads file bytes [offset, offset + out.size()); false when the file ends first.
  bool readAt(std::uint64_t offset, std::span<std::uint8_t> out) const;
  [[noreturn]] void failFile(const std::string& what) const;
  /// Checks the file header (magic, checksum, version) and sets file_bytes_ and version_.
  void readFileHeader();

  std::string path_;
  int fd_ = -1;
  std::uint64_t file_bytes_ = 0;
  std::uint32_t version_ = 0;
  std::vector<std::uint8_t> buffer_;  ///< capacity fixed at construction
  std::size_t position_ = 0;          ///< next unread byte in buffer_
  std::uint64_t offset_ = 0;          ///< file offset of buffer_'s end
  int next_section_ = 0;
  int current_section_ = -1;  ///< the section being read, −1 between sections
  int last_section_ = -1;     ///< the last section ended
  std::uint64_t section_offset_ = 0;
  std::uint64_t section_bytes_ = 0;
  std::uint64_t section_read_ = 0;
  std::uint32_t section_stored_crc_ = 0;
  bool section_checked_ = false;  ///< its checksum was checked when it was read whole
  Crc32 section_crc_;             ///< of the payload loaded so far
  std::array<std::uint64_t, kSectionCount> payload_bytes_{};
};

}  // namespace vifusion::mapfile
