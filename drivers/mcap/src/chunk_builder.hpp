#pragma once
// One chunk being filled: the Chunk record is assembled in place in one buffer (prefix space, then the
// Message records), the messages' data written straight into it by the caller (reserve, then commit),
// the CRC-32 of the records kept up to date per message, and each message's (channel, log time, offset)
// kept for the Message Index records that follow the chunk. Every buffer is sized at construction.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "record_builder.hpp"
#include "record_encoding.hpp"
#include "vifusion/core/crc32.hpp"
#include "vifusion/mcap/mcap_format.hpp"

namespace vifusion::mcap::detail {

class ChunkBuilder {
 public:
  /// @param records_capacity bytes of Message records one chunk may hold
  /// @param max_messages     messages one chunk may hold
  /// @param max_channel_id   largest channel id a message may carry
  ChunkBuilder(std::size_t records_capacity, std::size_t max_messages, std::uint16_t max_channel_id);

  bool empty() const { return entries_used_ == 0; }
  std::size_t messageCount() const { return entries_used_; }
  std::size_t recordsBytes() const { return records_used_; }
  bool indexFull() const { return entries_used_ == entries_.size(); }
  std::int64_t firstLogTimeNs() const { return first_log_time_ns_; }
  std::uint32_t channelMessageCount(std::uint16_t channel_id) const { return channel_message_counts_[channel_id]; }

  /// True when a message of up to `max_bytes` of data fits in this chunk.
  bool fits(std::size_t max_bytes) const;
  /// Space for the data of the next message, after its record prefix. Precondition: fits(max_bytes).
  std::span<std::uint8_t> reserve(std::size_t max_bytes);
  /// Completes the reserved message with its fields. Preconditions: bytes_used <= the reservation,
  /// 1 <= channel_id <= max_channel_id, times >= 0.
  void commit(std::uint16_t channel_id, std::uint32_t sequence, std::int64_t log_time_ns, std::int64_t publish_time_ns,
              std::size_t bytes_used);

  /// Fills in the chunk's prefix and returns the whole Chunk record. Precondition: !empty().
  std::span<const std::uint8_t> finishChunkRecord();
  /// The chunk's start and end log times and sizes, for its Chunk Index; call after finishChunkRecord().
  ChunkInfo info(std::uint64_t chunk_offset) const;
  /// Builds the Message Index records (one per channel with messages, ascending channel id) into the
  /// index buffer and appends each one's file offset to `offsets`, given the file offset the records will
  /// be written at.
  std::span<const std::uint8_t> buildMessageIndex(std::uint64_t index_offset, std::vector<ChannelIndexOffset>& offsets);
  /// Starts the next chunk.
  void clear();

 private:
  struct IndexEntry {
    std::int64_t log_time_ns = 0;
    std::uint64_t offset = 0;  ///< from the start of the records
    std::uint16_t channel_id = 0;
  };

  std::vector<std::uint8_t> buffer_;  ///< Chunk record prefix, then records
  std::size_t records_used_ = 0;
  Crc32 records_crc_;
  std::vector<IndexEntry> entries_;
  std::size_t entries_used_ = 0;
  std::vector<std::uint32_t> channel_message_counts_;  ///< per channel id, this chunk
  std::vector<std::size_t> channel_index_cursor_;      ///< per channel id, scatter position in index_
  RecordBuilder index_;
  std::int64_t first_log_time_ns_ = 0;
  std::int64_t start_time_ns_ = 0;
  std::int64_t end_time_ns_ = 0;
};

}  // namespace vifusion::mcap::detail
