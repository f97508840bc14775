#include "record_encoding.hpp"

#include "vifusion/core/crc32.hpp"
#include "vifusion/mcap/mcap_format.hpp"

namespace vifusion::mcap::detail {
namespace {

/// The data section CRC of DataEnd: 0, "not available". Every message byte already has its chunk's CRC
/// and a cut file, the case that matters, has no DataEnd at all; a second CRC over the whole data section
/// would cost another pass over ~30 MB/s of images on a 2-core robot computer for nothing more detected.
constexpr std::uint32_t kDataSectionCrcNotComputed = 0;

void appendChunkIndex(RecordBuilder& out, const ChunkIndexEntry& entry,
                      std::span<const ChannelIndexOffset> channel_offsets) {
  const std::size_t start = out.beginRecord(Opcode::kChunkIndex);
  out.time(entry.chunk.message_start_time_ns);
  out.time(entry.chunk.message_end_time_ns);
  out.u64(entry.chunk.offset);
  out.u64(entry.chunk.record_bytes);
  const std::size_t map = out.beginLengthPrefix();
  for (const ChannelIndexOffset& channel :
       channel_offsets.subspan(entry.first_channel_offset, entry.channel_offset_count)) {
    out.u16(channel.channel_id);
    out.u64(channel.offset);
  }
  out.endLengthPrefix(map);
  out.u64(entry.message_index_length);
  out.string(kCompressionNone);
  out.u64(entry.chunk.records_bytes);  // compressed_size: the same bytes, uncompressed
  out.u64(entry.chunk.records_bytes);
  out.endRecord(start);
}

void appendAttachmentIndex(RecordBuilder& out, const AttachmentIndexEntry& attachment) {
  const std::size_t start = out.beginRecord(Opcode::kAttachmentIndex);
  out.u64(attachment.offset);
  out.u64(attachment.record_bytes);
  out.time(attachment.log_time_ns);
  out.time(attachment.create_time_ns);
  out.u64(attachment.data_bytes);
  out.string(attachment.name);
  out.string(attachment.media_type);
  out.endRecord(start);
}

void appendStatistics(RecordBuilder& out, const McapStatistics& statistics) {
  const std::size_t start = out.beginRecord(Opcode::kStatistics);
  out.u64(statistics.message_count);
  out.u16(statistics.schema_count);
  out.u32(statistics.channel_count);
  out.u32(statistics.attachment_count);
  out.u32(statistics.metadata_count);
  out.u32(statistics.chunk_count);
  out.time(statistics.message_start_time_ns);
  out.time(statistics.message_end_time_ns);
  const std::size_t map = out.beginLengthPrefix();
  for (const auto& [channel_id, count] : statistics.channel_message_counts) {
    out.u16(channel_id);
    out.u64(count);
  }
  out.endLengthPrefix(map);
  out.endRecord(start);
}

/// One summary group: its opcode and where its records lie in the file.
struct SummaryGroup {
  Opcode opcode;
  std::uint64_t start = 0;
  std::uint64_t length = 0;
};

}  // namespace

void appendHeader(RecordBuilder& out, std::string_view profile, std::string_view library) {
  const std::size_t start = out.beginRecord(Opcode::kHeader);
  out.string(profile);
  out.string(library);
  out.endRecord(start);
}

void appendSchema(RecordBuilder& out, const SchemaInfo& schema) {
  const std::size_t start = out.beginRecord(Opcode::kSchema);
  out.u16(schema.id);
  out.string(schema.name);
  out.string(schema.encoding);
  out.u32(static_cast<std::uint32_t>(schema.data.size()));
  out.raw(schema.data);
  out.endRecord(start);
}

void appendChannel(RecordBuilder& out, const ChannelInfo& channel) {
  const std::size_t start = out.beginRecord(Opcode::kChannel);
  out.u16(channel.id);
  out.u16(channel.schema_id);
  out.string(channel.topic);
  out.string(channel.message_encoding);
  out.stringMap(channel.metadata);
  out.endRecord(start);
}

void appendAttachmentFields(RecordBuilder& out, const AttachmentIndexEntry& attachment) {
  out.time(attachment.log_time_ns);
  out.time(attachment.create_time_ns);
  out.string(attachment.name);
  out.string(attachment.media_type);
  out.u64(attachment.data_bytes);
}

void appendDataEndToMagic(RecordBuilder& out, std::uint64_t start_offset, const SummaryContent& summary) {
  const std::size_t base = out.size();
  const auto fileOffset = [&] { return start_offset + (out.size() - base); };

  const std::size_t data_end = out.beginRecord(Opcode::kDataEnd);
  out.u32(kDataSectionCrcNotComputed);
  out.endRecord(data_end);

  // Summary: every group holds records of one opcode (the specification requires the grouping).
  const std::size_t summary_position = out.size();
  const std::uint64_t summary_start = fileOffset();
  SummaryGroup groups[5] = {
      {Opcode::kSchema}, {Opcode::kChannel}, {Opcode::kChunkIndex}, {Opcode::kAttachmentIndex}, {Opcode::kStatistics}};
  const auto group = [&](SummaryGroup& g, auto&& append_records) {
    g.start = fileOffset();
    append_records();
    g.length = fileOffset() - g.start;
  };
  group(groups[0], [&] {
    for (const SchemaInfo& schema : summary.schemas) appendSchema(out, schema);
  });
  group(groups[1], [&] {
    for (const ChannelInfo& channel : summary.channels) appendChannel(out, channel);
  });
  group(groups[2], [&] {
    for (const ChunkIndexEntry& chunk : summary.chunks) appendChunkIndex(out, chunk, summary.channel_offsets);
  });
  group(groups[3], [&] {
    for (const AttachmentIndexEntry& attachment : summary.attachments) appendAttachmentIndex(out, attachment);
  });
  group(groups[4], [&] { appendStatistics(out, summary.statistics); });

  const std::uint64_t summary_offset_start = fileOffset();
  for (const SummaryGroup& g : groups) {
    if (g.length == 0) continue;
    const std::size_t start = out.beginRecord(Opcode::kSummaryOffset);
    out.u8(static_cast<std::uint8_t>(g.opcode));
    out.u64(g.start);
    out.u64(g.length);
    out.endRecord(start);
  }

  // Footer; its CRC covers the summary, the summary offsets and the footer up to summary_offset_start.
  // The length goes in first (not patched afterwards) because the CRC covers it.
  out.u8(static_cast<std::uint8_t>(Opcode::kFooter));
  out.u64(kFooterFieldsBytes);
  out.u64(summary_start);
  out.u64(summary_offset_start);
  out.u32(crc32(out.bytes().subspan(summary_position)));
  out.raw(kMagic);
}

}  // namespace vifusion::mcap::detail
