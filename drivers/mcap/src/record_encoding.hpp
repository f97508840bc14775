#pragma once
// The records the writer emits outside chunks, laid out as https://mcap.dev/spec defines them, and the
// close-time tail of a file: DataEnd, the summary (grouped by opcode), Summary Offsets, Footer, magic.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "record_builder.hpp"
#include "vifusion/mcap/mcap_records.hpp"

namespace vifusion::mcap::detail {

/// Where one channel's Message Index record after a chunk starts (file offset).
struct ChannelIndexOffset {
  std::uint16_t channel_id = 0;
  std::uint64_t offset = 0;
};

/// What a Chunk Index record says about one written chunk; its channel offsets are
/// [first_channel_offset, first_channel_offset + channel_offset_count) of the writer's offset table.
struct ChunkIndexEntry {
  ChunkInfo chunk;
  std::uint64_t message_index_length = 0;  ///< all Message Index records after the chunk [bytes]
  std::size_t first_channel_offset = 0;
  std::size_t channel_offset_count = 0;
};

/// What an Attachment Index record says about one written attachment.
struct AttachmentIndexEntry {
  std::uint64_t offset = 0;
  std::uint64_t record_bytes = 0;  ///< the whole Attachment record, opcode and length included
  std::int64_t log_time_ns = 0;
  std::int64_t create_time_ns = 0;
  std::uint64_t data_bytes = 0;
  std::string name;
  std::string media_type;
};

/// Everything the summary repeats or indexes.
struct SummaryContent {
  std::span<const SchemaInfo> schemas;
  std::span<const ChannelInfo> channels;
  std::span<const ChunkIndexEntry> chunks;
  std::span<const ChannelIndexOffset> channel_offsets;
  std::span<const AttachmentIndexEntry> attachments;
  McapStatistics statistics;
};

void appendHeader(RecordBuilder& out, std::string_view profile, std::string_view library);
void appendSchema(RecordBuilder& out, const SchemaInfo& schema);
void appendChannel(RecordBuilder& out, const ChannelInfo& channel);

/// The Attachment record's fields up to its data (log_time .. data length); the writer then appends the
/// data and the CRC-32 of everything from log_time on.
void appendAttachmentFields(RecordBuilder& out, const AttachmentIndexEntry& attachment);

/// DataEnd, then the summary and Summary Offset sections, the Footer (with the summary CRC) and the closing
/// magic. `out` starts at file offset `start_offset` (where the DataEnd record goes).
void appendDataEndToMagic(RecordBuilder& out, std::uint64_t start_offset, const SummaryContent& summary);

}  // namespace vifusion::mcap::detail
