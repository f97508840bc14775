#include "chunk_builder.hpp"

#include <algorithm>

#include "vifusion/core/little_endian.hpp"

namespace vifusion::mcap::detail {
namespace {

constexpr std::size_t kMessageIndexRecordPrefixBytes = kRecordHeaderBytes + kMessageIndexFieldsBytes;

// Field offsets in a Message record: channel_id u16, sequence u32, log_time u64, publish_time u64.
constexpr std::size_t kMessageChannelAt = kRecordHeaderBytes;
constexpr std::size_t kMessageSequenceAt = kMessageChannelAt + 2;
constexpr std::size_t kMessageLogTimeAt = kMessageSequenceAt + 4;
constexpr std::size_t kMessagePublishTimeAt = kMessageLogTimeAt + 8;

// Field offsets in an uncompressed Chunk record's prefix: message_start_time u64, message_end_time u64,
// uncompressed_size u64, uncompressed_crc u32, compression (u32 length 0), records length u64.
constexpr std::size_t kChunkStartTimeAt = kRecordHeaderBytes;
constexpr std::size_t kChunkEndTimeAt = kChunkStartTimeAt + 8;
constexpr std::size_t kChunkUncompressedSizeAt = kChunkEndTimeAt + 8;
constexpr std::size_t kChunkCrcAt = kChunkUncompressedSizeAt + 8;
constexpr std::size_t kChunkCompressionAt = kChunkCrcAt + 4;
constexpr std::size_t kChunkRecordsLengthAt = kChunkCompressionAt + 4;
static_assert(kChunkRecordsLengthAt + 8 == kChunkRecordPrefixBytes);
static_assert(kMessagePublishTimeAt + 8 == kMessageRecordPrefixBytes);

}  // namespace

ChunkBuilder::ChunkBuilder(std::size_t records_capacity, std::size_t max_messages, std::uint16_t max_channel_id)
    : buffer_(kChunkRecordPrefixBytes + records_capacity),
      entries_(max_messages),
      channel_message_counts_(static_cast<std::size_t>(max_channel_id) + 1, 0),
      channel_index_cursor_(static_cast<std::size_t>(max_channel_id) + 1, 0) {
  index_.reserve(static_cast<std::size_t>(max_channel_id) * kMessageIndexRecordPrefixBytes +
                 max_messages * kMessageIndexEntryBytes);
}

bool ChunkBuilder::fits(std::size_t max_bytes) const {
  const std::size_t free_bytes = buffer_.size() - kChunkRecordPrefixBytes - records_used_;
  return !indexFull() && free_bytes >= kMessageRecordPrefixBytes && free_bytes - kMessageRecordPrefixBytes >= max_bytes;
}

std::span<std::uint8_t> ChunkBuilder::reserve(std::size_t max_bytes) {
  return {buffer_.data() + kChunkRecordPrefixBytes + records_used_ + kMessageRecordPrefixBytes, max_bytes};
}

void ChunkBuilder::commit(std::uint16_t channel_id, std::uint32_t sequence, std::int64_t log_time_ns,
                          std::int64_t publish_time_ns, std::size_t bytes_used) {
  std::uint8_t* record = buffer_.data() + kChunkRecordPrefixBytes + records_used_;
  record[0] = static_cast<std::uint8_t>(Opcode::kMessage);
  storeU64(record + kRecordLengthAt, kMessageFieldsBytes + bytes_used);
  storeU16(record + kMessageChannelAt, channel_id);
  storeU32(record + kMessageSequenceAt, sequence);
  storeU64(record + kMessageLogTimeAt, static_cast<std::uint64_t>(log_time_ns));
  storeU64(record + kMessagePublishTimeAt, static_cast<std::uint64_t>(publish_time_ns));
  const std::size_t record_bytes = kMessageRecordPrefixBytes + bytes_used;
  records_crc_.update({record, record_bytes});

  entries_[entries_used_++] = {log_time_ns, records_used_, channel_id};
  ++channel_message_counts_[channel_id];
  if (entries_used_ == 1) {
    first_log_time_ns_ = start_time_ns_ = end_time_ns_ = log_time_ns;
  } else {
    start_time_ns_ = std::min(start_time_ns_, log_time_ns);
    end_time_ns_ = std::max(end_time_ns_, log_time_ns);
  }
  records_used_ += record_bytes;
}

std::span<const std::uint8_t> ChunkBuilder::finishChunkRecord() {
  std::uint8_t* prefix = buffer_.data();
  prefix[0] = static_cast<std::uint8_t>(Opcode::kChunk);
  storeU64(prefix + kRecordLengthAt, kChunkFieldsBytes + records_used_);
  storeU64(prefix + kChunkStartTimeAt, static_cast<std::uint64_t>(start_time_ns_));
  storeU64(prefix + kChunkEndTimeAt, static_cast<std::uint64_t>(end_time_ns_));
  storeU64(prefix + kChunkUncompressedSizeAt, records_used_);
  storeU32(prefix + kChunkCrcAt, records_crc_.value());
  storeU32(prefix + kChunkCompressionAt, 0);  // the empty string: uncompressed
  storeU64(prefix + kChunkRecordsLengthAt, records_used_);
  return {buffer_.data(), kChunkRecordPrefixBytes + records_used_};
}

ChunkInfo ChunkBuilder::info(std::uint64_t chunk_offset) const {
  ChunkInfo chunk;
  chunk.offset = chunk_offset;
  chunk.record_bytes = kChunkRecordPrefixBytes + records_used_;
  chunk.records_bytes = records_used_;
  chunk.message_start_time_ns = start_time_ns_;
  chunk.message_end_time_ns = end_time_ns_;
  return chunk;
}

std::span<const std::uint8_t> ChunkBuilder::buildMessageIndex(std::uint64_t index_offset,
                                                              std::vector<ChannelIndexOffset>& offsets) {
  // Lay out one record per channel, then scatter the entries into them in one pass (file order within a
  // channel, which is log-time order when the caller's log times do not go backwards).
  index_.clear();
  for (std::size_t channel = 0; channel < channel_message_counts_.size(); ++channel) {
    const std::uint32_t count = channel_message_counts_[channel];
    if (count == 0) continue;
    offsets.push_back({static_cast<std::uint16_t>(channel), index_offset + index_.size()});
    const std::size_t start = index_.beginRecord(Opcode::kMessageIndex);
    index_.u16(static_cast<std::uint16_t>(channel));
    index_.u32(static_cast<std::uint32_t>(count * kMessageIndexEntryBytes));
    channel_index_cursor_[channel] = index_.size();
    for (std::uint32_t i = 0; i < count; ++i) {
      index_.u64(0);
      index_.u64(0);
    }
    index_.endRecord(start);
  }
  std::uint8_t* out = index_.data();
  for (std::size_t i = 0; i < entries_used_; ++i) {
    const IndexEntry& entry = entries_[i];
    std::size_t& cursor = channel_index_cursor_[entry.channel_id];
    storeU64(out + cursor, static_cast<std::uint64_t>(entry.log_time_ns));
    storeU64(out + cursor + 8, entry.offset);
    cursor += kMessageIndexEntryBytes;
  }
  return index_.bytes();
}

void ChunkBuilder::clear() {
  records_used_ = 0;
  records_crc_.reset();
  entries_used_ = 0;
  std::fill(channel_message_counts_.begin(), channel_message_counts_.end(), 0u);
}

}  // namespace vifusion::mcap::detail
