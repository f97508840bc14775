#include "record_parser.hpp"

#include <cstdio>
#include <limits>

#include "vifusion/core/crc32.hpp"
#include "vifusion/core/little_endian.hpp"
#include "vifusion/mcap/mcap_format.hpp"

namespace vifusion::mcap::detail {
namespace {

/// Parsing ends with the cursor's problem, prefixed with the record's name.
bool finish(const ByteCursor& cursor, const char* record, std::string& problem) {
  if (cursor.ok()) return true;
  problem = std::string(record) + "." + cursor.problem();
  return false;
}

}  // namespace

bool ByteCursor::take(std::uint64_t count, const char* field) {
  if (!ok()) return false;
  const std::size_t left = bytes_.size() - position_;
  if (count > left) {
    fail(field, "needs " + std::to_string(count) + " bytes, " + std::to_string(left) + " left");
    return false;
  }
  return true;
}

void ByteCursor::fail(const char* field, const std::string& what) {
  if (ok()) problem_ = std::string(field) + ": " + what;
}

std::uint8_t ByteCursor::u8(const char* field) {
  if (!take(1, field)) return 0;
  return bytes_[position_++];
}

std::uint16_t ByteCursor::u16(const char* field) {
  if (!take(2, field)) return 0;
  const std::uint16_t value = loadU16(bytes_.data() + position_);
  position_ += 2;
  return value;
}

std::uint32_t ByteCursor::u32(const char* field) {
  if (!take(4, field)) return 0;
  const std::uint32_t value = loadU32(bytes_.data() + position_);
  position_ += 4;
  return value;
}

std::uint64_t ByteCursor::u64(const char* field) {
  if (!take(8, field)) return 0;
  const std::uint64_t value = loadU64(bytes_.data() + position_);
  position_ += 8;
  return value;
}

std::int64_t ByteCursor::time(const char* field) {
  const std::uint64_t value = u64(field);
  if (value > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
    fail(field, std::to_string(value) + " ns is beyond int64 (year 2262)");
    return 0;
  }
  return static_cast<std::int64_t>(value);
}

std::span<const std::uint8_t> ByteCursor::bytes(std::uint64_t count, const char* field) {
  if (!take(count, field)) return {};
  const std::span<const std::uint8_t> out = bytes_.subspan(position_, static_cast<std::size_t>(count));
  position_ += static_cast<std::size_t>(count);
  return out;
}

std::string_view ByteCursor::string(const char* field) {
  const std::uint32_t length = u32(field);
  const std::span<const std::uint8_t> text = bytes(length, field);
  return {reinterpret_cast<const char*>(text.data()), text.size()};
}

ByteCursor ByteCursor::lengthPrefixed(const char* field) {
  const std::uint32_t length = u32(field);
  ByteCursor inner(bytes(length, field));
  if (!ok()) inner.fail(field, "missing");
  return inner;
}

bool parseHeader(std::span<const std::uint8_t> content, HeaderFields& out, std::string& problem) {
  ByteCursor c(content);
  out.profile = c.string("profile");
  out.library = c.string("library");
  return finish(c, "Header", problem);
}

bool parseFooter(std::span<const std::uint8_t> content, FooterFields& out, std::string& problem) {
  ByteCursor c(content);
  out.summary_start = c.u64("summary_start");
  out.summary_offset_start = c.u64("summary_offset_start");
  out.summary_crc = c.u32("summary_crc");
  return finish(c, "Footer", problem);
}

bool parseSchema(std::span<const std::uint8_t> content, SchemaInfo& out, std::string& problem) {
  ByteCursor c(content);
  out.id = c.u16("id");
  out.name = c.string("name");
  out.encoding = c.string("encoding");
  const std::uint32_t data_length = c.u32("data");
  const std::span<const std::uint8_t> data = c.bytes(data_length, "data");
  out.data.assign(data.begin(), data.end());
  return finish(c, "Schema", problem);
}

bool parseChannel(std::span<const std::uint8_t> content, ChannelInfo& out, std::string& problem) {
  ByteCursor c(content);
  out.id = c.u16("id");
  out.schema_id = c.u16("schema_id");
  out.topic = c.string("topic");
  out.message_encoding = c.string("message_encoding");
  ByteCursor map = c.lengthPrefixed("metadata");
  out.metadata.clear();
  while (!map.atEnd()) {
    const std::string_view key = map.string("metadata key");
    const std::string_view value = map.string("metadata value");
    if (map.ok()) out.metadata.insert_or_assign(std::string(key), std::string(value));
  }
  if (!map.ok()) c.fail("metadata", map.problem());
  return finish(c, "Channel", problem);
}

bool parseMessage(std::span<const std::uint8_t> content, MessageFields& out, std::string& problem) {
  ByteCursor c(content);
  out.channel_id = c.u16("channel_id");
  out.sequence = c.u32("sequence");
  out.log_time_ns = c.time("log_time");
  out.publish_time_ns = c.time("publish_time");
  out.data = c.ok() ? content.subspan(c.position()) : std::span<const std::uint8_t>();
  return finish(c, "Message", problem);
}

bool parseChunk(std::span<const std::uint8_t> content, ChunkFields& out, std::string& problem) {
  ByteCursor c(content);
  out.message_start_time_ns = c.time("message_start_time");
  out.message_end_time_ns = c.time("message_end_time");
  out.uncompressed_size = c.u64("uncompressed_size");
  out.uncompressed_crc = c.u32("uncompressed_crc");
  out.compression = c.string("compression");
  const std::uint64_t records_length = c.u64("records");
  out.records = c.bytes(records_length, "records");
  if (!finish(c, "Chunk", problem)) return false;
  if (out.compression != kCompressionNone) {
    problem = "Chunk.compression: \"" + std::string(out.compression) + "\" is not supported (only uncompressed chunks)";
    return false;
  }
  if (out.uncompressed_size != out.records.size()) {
    problem = "Chunk.uncompressed_size: " + std::to_string(out.uncompressed_size) + " bytes, but its records hold " +
              std::to_string(out.records.size());
    return false;
  }
  if (out.uncompressed_crc != 0) {
    const std::uint32_t computed = crc32(out.records);
    if (computed != out.uncompressed_crc) {
      problem = "Chunk.uncompressed_crc: CRC mismatch: stored " + hex32(out.uncompressed_crc) + ", records give " +
                hex32(computed);
      return false;
    }
  }
  return true;
}

bool parseChunkIndex(std::span<const std::uint8_t> content, ChunkIndexFields& out, std::string& problem) {
  ByteCursor c(content);
  out.message_start_time_ns = c.time("message_start_time");
  out.message_end_time_ns = c.time("message_end_time");
  out.chunk_start_offset = c.u64("chunk_start_offset");
  out.chunk_length = c.u64("chunk_length");
  c.lengthPrefixed("message_index_offsets");  // not needed: the reader walks chunks whole
  out.message_index_length = c.u64("message_index_length");
  out.compression = c.string("compression");
  out.compressed_size = c.u64("compressed_size");
  out.uncompressed_size = c.u64("uncompressed_size");
  return finish(c, "ChunkIndex", problem);
}

bool parseAttachment(std::span<const std::uint8_t> content, AttachmentInfo& out, std::string& problem) {
  ByteCursor c(content);
  out.log_time_ns = c.time("log_time");
  out.create_time_ns = c.time("create_time");
  out.name = c.string("name");
  out.media_type = c.string("media_type");
  const std::uint64_t data_length = c.u64("data");
  const std::span<const std::uint8_t> data = c.bytes(data_length, "data");
  const std::size_t crc_covered = c.position();
  const std::uint32_t stored_crc = c.u32("crc");
  if (!finish(c, "Attachment", problem)) return false;
  out.data.assign(data.begin(), data.end());
  if (stored_crc != 0) {
    const std::uint32_t computed = crc32(content.first(crc_covered));
    if (computed != stored_crc) {
      problem =
          "Attachment.crc: CRC mismatch: stored " + hex32(stored_crc) + ", fields and data give " + hex32(computed);
      return false;
    }
  }
  return true;
}

bool parseAttachmentIndex(std::span<const std::uint8_t> content, AttachmentIndexFields& out, std::string& problem) {
  ByteCursor c(content);
  out.offset = c.u64("offset");
  out.length = c.u64("length");
  c.time("log_time");
  c.time("create_time");
  c.u64("data_size");
  out.name = c.string("name");
  c.string("media_type");
  return finish(c, "AttachmentIndex", problem);
}

bool parseStatistics(std::span<const std::uint8_t> content, McapStatistics& out, std::string& problem) {
  ByteCursor c(content);
  out.message_count = c.u64("message_count");
  out.schema_count = c.u16("schema_count");
  out.channel_count = c.u32("channel_count");
  out.attachment_count = c.u32("attachment_count");
  out.metadata_count = c.u32("metadata_count");
  out.chunk_count = c.u32("chunk_count");
  out.message_start_time_ns = c.time("message_start_time");
  out.message_end_time_ns = c.time("message_end_time");
  ByteCursor map = c.lengthPrefixed("channel_message_counts");
  out.channel_message_counts.clear();
  while (!map.atEnd()) {
    const std::uint16_t channel_id = map.u16("channel id");
    const std::uint64_t count = map.u64("message count");
    if (map.ok()) out.channel_message_counts.insert_or_assign(channel_id, count);
  }
  if (!map.ok()) c.fail("channel_message_counts", map.problem());
  return finish(c, "Statistics", problem);
}

bool sameSchema(const SchemaInfo& a, const SchemaInfo& b) {
  return a.id == b.id && a.name == b.name && a.encoding == b.encoding && a.data == b.data;
}

bool sameChannel(const ChannelInfo& a, const ChannelInfo& b) {
  return a.id == b.id && a.schema_id == b.schema_id && a.topic == b.topic && a.message_encoding == b.message_encoding &&
         a.metadata == b.metadata;
}

bool nextRecord(std::span<const std::uint8_t> bytes, std::size_t& position, RawRecord& out, std::string& problem) {
  problem.clear();
  if (position >= bytes.size()) return false;
  const std::size_t left = bytes.size() - position;
  if (left < kRecordHeaderBytes) {
    problem = "ends inside a record header at offset " + std::to_string(position) + " (" + std::to_string(left) +
              " of " + std::to_string(kRecordHeaderBytes) + " bytes)";
    return false;
  }
  const std::uint8_t opcode = bytes[position];
  const std::uint64_t length = loadU64(bytes.data() + position + kRecordLengthAt);
  if (length > left - kRecordHeaderBytes) {
    problem = "ends inside a " + std::string(opcodeName(opcode)) + " record at offset " + std::to_string(position) +
              " (content of " + std::to_string(length) + " bytes, " + std::to_string(left - kRecordHeaderBytes) +
              " present)";
    return false;
  }
  out.opcode = opcode;
  out.offset = position;
  out.content = bytes.subspan(position + kRecordHeaderBytes, static_cast<std::size_t>(length));
  position += kRecordHeaderBytes + static_cast<std::size_t>(length);
  return true;
}

std::string hex32(std::uint32_t value) {
  char text[sizeof("0x12345678")];
  std::snprintf(text, sizeof(text), "0x%08x", value);
  return text;
}

}  // namespace vifusion::mcap::detail
