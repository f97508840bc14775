// The reader's fast path: a complete file's Footer and summary (https://mcap.dev/spec, "Summary Section").
// Anything unexpected makes the summary unusable, and McapReader then scans the data section instead, so
// a damaged summary costs time, never messages.

#include <algorithm>
#include <vector>

#include "record_parser.hpp"
#include "recording_contents.hpp"
#include "vifusion/core/crc32.hpp"
#include "vifusion/core/little_endian.hpp"
#include "vifusion/mcap/mcap_format.hpp"

namespace vifusion::mcap::detail {
namespace {

constexpr std::size_t kDataEndRecordBytes = kRecordHeaderBytes + kDataEndFieldsBytes;
/// Footer bytes the summary CRC covers: opcode, length, summary_start, summary_offset_start.
constexpr std::size_t kFooterCrcCoveredBytes = kRecordHeaderBytes + 8 + 8;
/// Largest summary read into memory. A ten-hour recording's is ~80 MB (one ~100-byte Chunk Index per
/// 50 ms chunk); a Footer pointing further back is damaged, and the scan is then the better way.
constexpr std::uint64_t kMaxSummaryBytes = 256 * 1024 * 1024;

std::vector<std::uint8_t> readRange(const ByteSource& source, std::uint64_t offset, std::uint64_t bytes) {
  std::vector<std::uint8_t> out(static_cast<std::size_t>(bytes));
  source.read(offset, out);
  return out;
}

/// Loads the attachment an Attachment Index points at (it must lie in the data section).
bool loadAttachment(const ByteSource& source, const AttachmentIndexFields& index, std::uint64_t data_end,
                    RecordingContents& contents, std::string& problem) {
  const std::string where = "AttachmentIndex \"" + index.name + "\" (offset " + std::to_string(index.offset) + ", " +
                            std::to_string(index.length) + " bytes)";
  if (index.offset < contents.header_end || index.offset > data_end || index.length > data_end - index.offset ||
      index.length < kRecordHeaderBytes) {
    problem = where + " points outside the data section";
    return false;
  }
  const std::vector<std::uint8_t> record = readRange(source, index.offset, index.length);
  if (record[0] != static_cast<std::uint8_t>(Opcode::kAttachment) ||
      loadU64(record.data() + kRecordLengthAt) != index.length - kRecordHeaderBytes) {
    problem = where + " does not point at an Attachment record of that length";
    return false;
  }
  AttachmentInfo attachment;
  if (!parseAttachment(std::span(record).subspan(kRecordHeaderBytes), attachment, problem)) {
    problem = where + ": " + problem;
    return false;
  }
  contents.attachments.push_back(std::move(attachment));
  return true;
}

bool readSummaryRecords(const ByteSource& source, std::span<const std::uint8_t> summary, std::uint64_t data_end,
                        RecordingContents& contents, bool& have_statistics, std::string& problem) {
  std::size_t position = 0;
  RawRecord record;
  while (nextRecord(summary, position, record, problem)) {
    switch (static_cast<Opcode>(record.opcode)) {
      case Opcode::kSchema: {
        SchemaInfo schema;
        if (!parseSchema(record.content, schema, problem) || !contents.addSchema(std::move(schema), problem)) {
          return false;
        }
        break;
      }
      case Opcode::kChannel: {
        ChannelInfo channel;
        if (!parseChannel(record.content, channel, problem) || !contents.addChannel(std::move(channel), problem)) {
          return false;
        }
        break;
      }
      case Opcode::kChunkIndex: {
        ChunkIndexFields index;
        if (!parseChunkIndex(record.content, index, problem)) return false;
        if (index.chunk_start_offset < contents.header_end || index.chunk_start_offset > data_end ||
            index.chunk_length > data_end - index.chunk_start_offset || index.chunk_length < kChunkRecordPrefixBytes) {
          problem = "ChunkIndex: the chunk at offset " + std::to_string(index.chunk_start_offset) + " (" +
                    std::to_string(index.chunk_length) + " bytes) lies outside the data section";
          return false;
        }
        if (index.compression != kCompressionNone) {
          problem = "ChunkIndex: the chunk at offset " + std::to_string(index.chunk_start_offset) +
                    " is compressed (\"" + std::string(index.compression) + "\"), which this reader does not support";
          return false;
        }
        contents.chunks.push_back({index.chunk_start_offset, index.chunk_length, index.uncompressed_size,
                                   index.message_start_time_ns, index.message_end_time_ns});
        break;
      }
      case Opcode::kAttachmentIndex: {
        AttachmentIndexFields index;
        if (!parseAttachmentIndex(record.content, index, problem) ||
            !loadAttachment(source, index, data_end, contents, problem)) {
          return false;
        }
        break;
      }
      case Opcode::kStatistics:
        if (have_statistics) {
          problem = "a second Statistics record";
          return false;
        }
        if (!parseStatistics(record.content, contents.statistics, problem)) return false;
        have_statistics = true;
        break;
      case Opcode::kMetadataIndex:
      case Opcode::kSummaryOffset:
        break;
      default:
        if (record.opcode < kFirstUndefinedOpcode) {
          problem = "a " + std::string(opcodeName(record.opcode)) + " record is not allowed in the summary";
          return false;
        }
        break;  // reserved and private records: skipped, as the specification asks
    }
  }
  return problem.empty();
}

}  // namespace

bool readSummary(const ByteSource& source, RecordingContents& contents, std::string& problem) {
  const std::uint64_t size = source.size();
  if (size < contents.header_end + kDataEndRecordBytes + kFooterAndMagicBytes) {
    problem = "the file is too short to end with DataEnd, Footer and magic (" + std::to_string(size) + " bytes)";
    return false;
  }
  const std::uint64_t footer_offset = size - kFooterAndMagicBytes;
  const std::vector<std::uint8_t> tail = readRange(source, footer_offset, kFooterAndMagicBytes);
  if (!std::equal(kMagic.begin(), kMagic.end(), tail.end() - kMagic.size())) {
    problem = "the file does not end with the MCAP magic (it was cut while recording)";
    return false;
  }
  FooterFields footer;
  if (tail[0] != static_cast<std::uint8_t>(Opcode::kFooter) ||
      loadU64(tail.data() + kRecordLengthAt) != kFooterFieldsBytes ||
      !parseFooter(std::span(tail).subspan(kRecordHeaderBytes, kFooterFieldsBytes), footer, problem)) {
    problem = "no Footer record before the closing magic at offset " + std::to_string(footer_offset);
    return false;
  }
  if (footer.summary_start == 0) {
    problem = "the Footer says the file has no summary";
    return false;
  }
  if (footer.summary_start < contents.header_end + kDataEndRecordBytes || footer.summary_start > footer_offset) {
    problem = "Footer.summary_start " + std::to_string(footer.summary_start) + " is outside the file (" +
              std::to_string(contents.header_end) + " .. " + std::to_string(footer_offset) + ")";
    return false;
  }
  const std::uint64_t data_end = footer.summary_start - kDataEndRecordBytes;
  if (footer_offset - data_end > kMaxSummaryBytes) {
    problem = "Footer.summary_start " + std::to_string(footer.summary_start) + " makes the summary " +
              std::to_string(footer_offset - footer.summary_start) + " bytes long, more than the " +
              std::to_string(kMaxSummaryBytes) + " a recording's summary can be";
    return false;
  }
  const std::vector<std::uint8_t> region = readRange(source, data_end, footer_offset - data_end);
  if (region[0] != static_cast<std::uint8_t>(Opcode::kDataEnd) ||
      loadU64(region.data() + kRecordLengthAt) != kDataEndFieldsBytes) {
    problem = "no DataEnd record just before the summary (offset " + std::to_string(data_end) + ")";
    return false;
  }
  const std::span<const std::uint8_t> summary_and_offsets = std::span(region).subspan(kDataEndRecordBytes);
  if (footer.summary_crc != 0) {
    Crc32 crc;
    crc.update(summary_and_offsets);
    crc.update(std::span(tail).first(kFooterCrcCoveredBytes));
    if (crc.value() != footer.summary_crc) {
      problem = "Footer.summary_crc: CRC mismatch: stored " + hex32(footer.summary_crc) + ", summary gives " +
                hex32(crc.value());
      return false;
    }
  }
  // The summary proper ends where the Summary Offset section starts (or at the Footer).
  std::uint64_t summary_bytes = summary_and_offsets.size();
  if (footer.summary_offset_start != 0) {
    if (footer.summary_offset_start < footer.summary_start || footer.summary_offset_start > footer_offset) {
      problem =
          "Footer.summary_offset_start " + std::to_string(footer.summary_offset_start) + " is outside the summary";
      return false;
    }
    summary_bytes = footer.summary_offset_start - footer.summary_start;
  }
  bool have_statistics = false;
  if (!readSummaryRecords(source, summary_and_offsets.first(static_cast<std::size_t>(summary_bytes)), data_end,
                          contents, have_statistics, problem)) {
    problem = "summary: " + problem;
    return false;
  }
  if (contents.chunks.empty() && (!have_statistics || contents.statistics.message_count != 0)) {
    problem = "the summary indexes no chunk (messages outside chunks are found by scanning)";
    return false;
  }
  std::sort(contents.chunks.begin(), contents.chunks.end(),
            [](const ChunkInfo& a, const ChunkInfo& b) { return a.offset < b.offset; });
  for (const ChunkInfo& chunk : contents.chunks) contents.items.push_back({chunk.offset, chunk.record_bytes, true});
  if (!have_statistics) {
    contents.statistics.schema_count = static_cast<std::uint16_t>(contents.schemas.size());
    contents.statistics.channel_count = static_cast<std::uint32_t>(contents.channels.size());
    contents.statistics.attachment_count = static_cast<std::uint32_t>(contents.attachments.size());
    contents.statistics.chunk_count = static_cast<std::uint32_t>(contents.chunks.size());
  }
  return true;
}

}  // namespace vifusion::mcap::detail
