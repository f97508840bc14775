#pragma once
// Bounds-checked decoding of MCAP record contents (https://mcap.dev/spec). Every read is checked against
// the bytes that are there; a record that is too short, a length that points past its record, a time that
// does not fit int64 or a CRC that does not match gives false and a problem text naming the field, never a
// read out of bounds. Fields added to a record by later versions of the specification are ignored.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "vifusion/mcap/mcap_records.hpp"

namespace vifusion::mcap::detail {

/// Reads fields front to back; after the first overrun every read gives zero/empty and ok() is false.
class ByteCursor {
 public:
  explicit ByteCursor(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}

  bool ok() const { return problem_.empty(); }
  /// "<field>: needs 8 bytes, 3 left" for the first failed read.
  const std::string& problem() const { return problem_; }
  std::size_t position() const { return position_; }
  /// True when every byte has been read (or a read failed).
  bool atEnd() const { return !ok() || position_ == bytes_.size(); }

  std::uint8_t u8(const char* field);
  std::uint16_t u16(const char* field);
  std::uint32_t u32(const char* field);
  std::uint64_t u64(const char* field);
  /// A Timestamp (u64 ns) as int64 ns; values of 2^63 ns and more (year 2262) are refused.
  std::int64_t time(const char* field);
  std::span<const std::uint8_t> bytes(std::uint64_t count, const char* field);
  /// String: u32 length + bytes.
  std::string_view string(const char* field);
  /// The elements of a u32-length-prefixed Array or Map, as a cursor of their own.
  ByteCursor lengthPrefixed(const char* field);
  /// Marks the cursor failed with `what` (the first problem is kept).
  void fail(const char* field, const std::string& what);

 private:
  bool take(std::uint64_t count, const char* field);

  std::span<const std::uint8_t> bytes_;
  std::size_t position_ = 0;
  std::string problem_;
};

struct HeaderFields {
  std::string profile;
  std::string library;
};

struct FooterFields {
  std::uint64_t summary_start = 0;
  std::uint64_t summary_offset_start = 0;
  std::uint32_t summary_crc = 0;
};

/// A Message record; data points into the parsed bytes.
struct MessageFields {
  std::uint16_t channel_id = 0;
  std::uint32_t sequence = 0;
  std::int64_t log_time_ns = 0;
  std::int64_t publish_time_ns = 0;
  std::span<const std::uint8_t> data;
};

/// A Chunk record; compression and records point into the parsed bytes.
struct ChunkFields {
  std::int64_t message_start_time_ns = 0;
  std::int64_t message_end_time_ns = 0;
  std::uint64_t uncompressed_size = 0;
  std::uint32_t uncompressed_crc = 0;
  std::string_view compression;
  std::span<const std::uint8_t> records;
};

struct ChunkIndexFields {
  std::int64_t message_start_time_ns = 0;
  std::int64_t message_end_time_ns = 0;
  std::uint64_t chunk_start_offset = 0;
  std::uint64_t chunk_length = 0;
  std::uint64_t message_index_length = 0;
  std::string_view compression;
  std::uint64_t compressed_size = 0;
  std::uint64_t uncompressed_size = 0;
};

struct AttachmentIndexFields {
  std::uint64_t offset = 0;
  std::uint64_t length = 0;
  std::string name;
};

/// Each parser decodes one record's content (what follows opcode and length). False with `problem` set
/// ("Channel.topic: needs 12 bytes, 4 left") when the content is malformed.
bool parseHeader(std::span<const std::uint8_t> content, HeaderFields& out, std::string& problem);
bool parseFooter(std::span<const std::uint8_t> content, FooterFields& out, std::string& problem);
bool parseSchema(std::span<const std::uint8_t> content, SchemaInfo& out, std::string& problem);
bool parseChannel(std::span<const std::uint8_t> content, ChannelInfo& out, std::string& problem);
bool parseMessage(std::span<const std::uint8_t> content, MessageFields& out, std::string& problem);
/// Also checks what the reader relies on: no compression, uncompressed_size equal to the records' length,
/// and the records' CRC-32 when it is not 0 ("not computed").
bool parseChunk(std::span<const std::uint8_t> content, ChunkFields& out, std::string& problem);
bool parseChunkIndex(std::span<const std::uint8_t> content, ChunkIndexFields& out, std::string& problem);
/// Also checks the attachment's CRC-32 when it is not 0.
bool parseAttachment(std::span<const std::uint8_t> content, AttachmentInfo& out, std::string& problem);
bool parseAttachmentIndex(std::span<const std::uint8_t> content, AttachmentIndexFields& out, std::string& problem);
bool parseStatistics(std::span<const std::uint8_t> content, McapStatistics& out, std::string& problem);

/// True when two definitions of the same id agree (the specification requires it of repeated records).
bool sameSchema(const SchemaInfo& a, const SchemaInfo& b);
bool sameChannel(const ChannelInfo& a, const ChannelInfo& b);

/// One record of a sequence of records (a chunk's records, the summary section).
struct RawRecord {
  std::uint8_t opcode = 0;
  std::size_t offset = 0;  ///< of its opcode byte, within the sequence
  std::span<const std::uint8_t> content;
};

/// The record at `position` of `bytes`, advancing `position` past it. False at the end (problem empty) or
/// when the rest is no complete record (problem says so: "ends inside a Message record at offset 96 ...").
bool nextRecord(std::span<const std::uint8_t> bytes, std::size_t& position, RawRecord& out, std::string& problem);

/// "0x1234abcd".
std::string hex32(std::uint32_t value);

}  // namespace vifusion::mcap::detail
