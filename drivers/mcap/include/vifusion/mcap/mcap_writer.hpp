#pragma once
// McapWriter: records messages into an MCAP file (https://mcap.dev/spec) that survives the recording being
// cut anywhere — killed, out of power, out of disk. Messages go into uncompressed chunks, each with the
// CRC-32 of its records and followed by its Message Index records; a chunk is written when it reaches
// chunk_target_bytes or, at the caller's flushIfDue(now), when it is chunk_flush_ns old, and (by default)
// fdatasync'd. A cut file therefore holds every chunk written before the cut, and McapReader reads them
// without the summary that close() would have added.
//
// Schemas and channels are written into the data section when registered (so before any chunk that uses
// them, and so a cut file still has them) and repeated in the summary at close(), with a Chunk Index per
// chunk, an Attachment Index per attachment and the Statistics.
//
// Per message, nothing is allocated and nothing throws: reserveMessage() hands out space inside the chunk
// buffer for the caller to serialise into, commitMessage() completes the record. The first write or
// fdatasync error (ENOSPC, EIO, EBADF after the storage went away) puts the writer in a failed state that
// keeps the message (path, byte offset, errno text); every later call is then a no-op returning false.
// One thread uses a writer (the recorder's); nothing in it locks.
//
//   McapWriter writer;                                   // options validated, buffers sized here
//   if (!writer.open("run.mcap")) report(writer.error());
//   const uint16_t imu_schema = writer.registerSchema("sensor_msgs/msg/Imu", "ros2msg", imu_msg_text);
//   const uint16_t imu = writer.registerChannel("/imu", imu_schema, "cdr");
//   std::span<uint8_t> space = writer.reserveMessage(kImuCdrBytes);
//   const size_t used = serialise(sample, space);
//   writer.commitMessage(imu, seq, now_ns, sample.t_ns, used);
//   writer.flushIfDue(now_ns);                           // also from a timer when no message comes
//   ...
//   writer.close();                                      // summary, footer

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "vifusion/mcap/mcap_records.hpp"
#include "vifusion/mcap/mcap_writer_options.hpp"

namespace vifusion::mcap {

namespace detail {
class ChunkBuilder;
class FileSink;
class RecordBuilder;
struct ChunkIndexEntry;
struct ChannelIndexOffset;
struct AttachmentIndexEntry;
}  // namespace detail

class McapWriter {
 public:
  /// What registerSchema()/registerChannel() return when the writer has failed: no id was assigned.
  static constexpr std::uint16_t kNoId = 0;

  /// Validates the options and sizes every buffer the per-message path uses.
  /// @throws vifusion::Error naming a bad option.
  explicit McapWriter(McapWriterOptions options = {});
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;
  /// Closes the file (summary included) if it is still open.
  ~McapWriter();

  /// Creates (truncates) `path` and writes the magic and the Header. False, with error(), when the file
  /// cannot be created or written. A writer records one file at a time; after close() it may open another.
  /// @throws vifusion::Error when a file is already open.
  bool open(const std::string& path);

  /// Defines a schema (ROS 2: name "sensor_msgs/msg/Imu", encoding "ros2msg", data the message definition)
  /// and writes its record. @return its id (1, 2, ...), or kNoId when the writer has failed.
  /// @throws vifusion::Error when not open, the name is empty, data comes without an encoding, or
  /// max_channels schemas exist already.
  std::uint16_t registerSchema(std::string_view name, std::string_view encoding, std::span<const std::uint8_t> data);
  /// Defines a channel on a registered schema (or kNoId for none) and writes its record.
  /// @return its id (1, 2, ...), or kNoId when the writer has failed.
  /// @throws vifusion::Error when not open, the topic or encoding is empty, the schema is unknown, or
  /// max_channels channels exist already.
  std::uint16_t registerChannel(std::string_view topic, std::uint16_t schema_id, std::string_view message_encoding,
                                const std::map<std::string, std::string>& metadata = {});

  /// Space for the data of the next message, up to `max_bytes`, inside the current chunk (a full chunk is
  /// written first). Valid until commitMessage(), or the next reserveMessage() which abandons it. Empty
  /// when the writer is not open or has failed, or when max_bytes > max_message_bytes (counted as rejected).
  std::span<std::uint8_t> reserveMessage(std::size_t max_bytes);
  /// Completes the reserved message with `bytes_used` of its space. False when the writer has failed, or
  /// when the message is rejected (counted, the first reason kept): no reservation, bytes_used beyond it,
  /// an unregistered channel, a negative time.
  bool commitMessage(std::uint16_t channel_id, std::uint32_t sequence, std::int64_t log_time_ns,
                     std::int64_t publish_time_ns, std::size_t bytes_used);
  /// reserveMessage() + copy + commitMessage(), for data that already exists.
  bool write(std::uint16_t channel_id, std::uint32_t sequence, std::int64_t log_time_ns, std::int64_t publish_time_ns,
             std::span<const std::uint8_t> data);
  /// Writes the current chunk if its first message was logged chunk_flush_ns or more before `now_ns` (same
  /// clock as the log times). Call after each message and from a timer. False once failed.
  bool flushIfDue(std::int64_t now_ns);
  /// Writes the current chunk now, if it holds any message. False once failed.
  bool flush();

  /// Stores a file (the rig's calibration YAML) as an Attachment record between chunks, indexed in the
  /// summary. Not for the per-message path (it may allocate). False once failed.
  /// @throws vifusion::Error when not open, the name is empty, or a time is negative.
  bool writeAttachment(std::string_view name, std::string_view media_type, std::span<const std::uint8_t> data,
                       std::int64_t log_time_ns, std::int64_t create_time_ns = 0);

  /// Writes the last chunk, DataEnd, the summary, the Footer and the closing magic, syncs and closes.
  /// DataEnd's data-section CRC is 0 ("not computed"): every message byte is covered by its chunk's CRC,
  /// a cut file has no DataEnd to check anyway, and a second CRC pass over all image bytes would cost CPU
  /// on the robot for nothing more detected. The Footer's summary CRC is computed.
  /// After a failure it only closes the file (McapReader still reads it; recoverMcap() completes it).
  /// False when anything failed, now or before. A no-op returning !failed() when nothing is open.
  bool close();

  bool isOpen() const;
  bool failed() const;
  /// What failed, where and why ("run.mcap: write of Chunk record failed at byte offset 1048576: No space
  /// left on device"); empty while nothing has.
  const std::string& error() const;
  /// Bytes in the file so far.
  std::uint64_t bytesWritten() const;
  /// Chunks completely written to the file.
  std::uint64_t chunksWritten() const { return chunks_written_; }
  /// Messages in those chunks: what a reader of the file finds even if the recording stops now.
  std::uint64_t messagesWritten() const { return messages_written_; }
  /// Messages refused by commitMessage()/reserveMessage() (see there); the first reason is kept.
  std::uint64_t messagesRejected() const { return messages_rejected_; }
  const std::string& firstRejection() const { return first_rejection_; }
  const McapWriterOptions& options() const { return options_; }

 private:
  bool writeChunk();
  /// Counts a rejected message; true for the first, whose reason the caller then keeps (composing the
  /// text only once, so a stream of rejections allocates nothing).
  bool countRejection();
  void requireOpen(const char* call) const;
  void resetCounters();

  McapWriterOptions options_;
  std::unique_ptr<detail::ChunkBuilder> chunk_;
  std::unique_ptr<detail::FileSink> sink_;
  std::unique_ptr<detail::RecordBuilder> scratch_;  ///< records outside chunks, built then written
  std::vector<SchemaInfo> schemas_;
  std::vector<ChannelInfo> channels_;                  ///< channels_[id - 1]
  std::vector<std::uint64_t> channel_message_counts_;  ///< per channel id, written chunks
  std::vector<detail::ChunkIndexEntry> chunk_index_;
  std::vector<detail::ChannelIndexOffset> channel_offsets_;
  std::vector<detail::AttachmentIndexEntry> attachments_;
  bool reservation_open_ = false;
  std::size_t reservation_bytes_ = 0;
  std::uint64_t chunks_written_ = 0;
  std::uint64_t messages_written_ = 0;
  std::uint64_t messages_rejected_ = 0;
  std::string first_rejection_;
  std::int64_t message_start_time_ns_ = 0;
  std::int64_t message_end_time_ns_ = 0;
};

}  // namespace vifusion::mcap
