#include "vifusion/mcap/mcap_writer.hpp"

#include <algorithm>
#include <cstring>
#include <utility>

#include "chunk_builder.hpp"
#include "file_sink.hpp"
#include "record_builder.hpp"
#include "record_encoding.hpp"
#include "vifusion/core/crc32.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/core/little_endian.hpp"
#include "vifusion/mcap/mcap_format.hpp"

namespace vifusion::mcap {
namespace {

/// Channels per chunk the Chunk Index offset table is reserved for (a vifusion recording has ~8
/// streams: depth, colour, their camera infos, IMU, sync edges, clock state, tf).
constexpr std::size_t kReservedChannelsPerChunk = 8;
/// Starting size of the buffer for records outside chunks (Header, Schema, Channel, Attachment fields).
constexpr std::size_t kScratchReserveBytes = 64 * kKiB;

std::string quoted(std::string_view text) {
  // Appended piecewise: GCC 12 misreports `"\"" + std::string(text)` under -Wrestrict (a known false positive).
  std::string out;
  out.reserve(text.size() + 2);
  out.append(1, '"').append(text).append(1, '"');
  return out;
}

}  // namespace

McapWriter::McapWriter(McapWriterOptions options) : options_(std::move(options)) {
  options_.validate();
  const std::size_t records_capacity =
      options_.chunk_target_bytes + kMessageRecordPrefixBytes + options_.max_message_bytes;
  chunk_ = std::make_unique<detail::ChunkBuilder>(records_capacity, options_.max_messages_per_chunk,
                                                  static_cast<std::uint16_t>(options_.max_channels));
  sink_ = std::make_unique<detail::FileSink>();
  scratch_ = std::make_unique<detail::RecordBuilder>();
  scratch_->reserve(kScratchReserveBytes);
  channel_message_counts_.assign(options_.max_channels + 1, 0);
  chunk_index_.reserve(options_.reserved_chunks);
  channel_offsets_.reserve(options_.reserved_chunks * std::min(options_.max_channels, kReservedChannelsPerChunk));
}

McapWriter::~McapWriter() { close(); }

bool McapWriter::isOpen() const { return sink_->isOpen(); }
bool McapWriter::failed() const { return sink_->failed(); }
const std::string& McapWriter::error() const { return sink_->error(); }
std::uint64_t McapWriter::bytesWritten() const { return sink_->offset(); }

void McapWriter::requireOpen(const char* call) const {
  if (!isOpen() && !failed()) throw Error(std::string("McapWriter::") + call + ": no file is open (call open first)");
}

void McapWriter::resetCounters() {
  chunk_->clear();
  schemas_.clear();
  channels_.clear();
  std::fill(channel_message_counts_.begin(), channel_message_counts_.end(), 0u);
  chunk_index_.clear();
  channel_offsets_.clear();
  attachments_.clear();
  reservation_open_ = false;
  chunks_written_ = messages_written_ = messages_rejected_ = 0;
  first_rejection_.clear();
  message_start_time_ns_ = message_end_time_ns_ = 0;
}

bool McapWriter::open(const std::string& path) {
  if (isOpen()) throw Error("McapWriter::open(" + path + "): " + sink_->path() + " is still open (close it first)");
  resetCounters();
  if (!sink_->open(path)) return false;
  scratch_->clear();
  scratch_->raw(kMagic);
  detail::appendHeader(*scratch_, options_.profile, options_.library);
  return sink_->write(scratch_->bytes(), "magic and Header");
}

std::uint16_t McapWriter::registerSchema(std::string_view name, std::string_view encoding,
                                         std::span<const std::uint8_t> data) {
  requireOpen("registerSchema");
  if (failed()) return kNoId;
  if (name.empty()) throw Error("McapWriter::registerSchema: the schema name is empty");
  if (encoding.empty() && !data.empty()) {
    throw Error("McapWriter::registerSchema(" + quoted(name) + "): " + std::to_string(data.size()) +
                " bytes of data without an encoding (ROS 2: \"ros2msg\")");
  }
  if (schemas_.size() >= options_.max_channels) {
    throw Error("McapWriter::registerSchema(" + quoted(name) +
                "): max_channels = " + std::to_string(options_.max_channels) + " schemas are registered already");
  }
  SchemaInfo schema;
  schema.id = static_cast<std::uint16_t>(schemas_.size() + 1);
  schema.name = name;
  schema.encoding = encoding;
  schema.data.assign(data.begin(), data.end());
  scratch_->clear();
  detail::appendSchema(*scratch_, schema);
  if (!sink_->write(scratch_->bytes(), "Schema record " + quoted(name))) return kNoId;
  schemas_.push_back(std::move(schema));
  return schemas_.back().id;
}

std::uint16_t McapWriter::registerChannel(std::string_view topic, std::uint16_t schema_id,
                                          std::string_view message_encoding,
                                          const std::map<std::string, std::string>& metadata) {
  requireOpen("registerChannel");
  if (failed()) return kNoId;
  if (topic.empty()) throw Error("McapWriter::registerChannel: the topic is empty");
  if (message_encoding.empty()) {
    throw Error("McapWriter::registerChannel(" + quoted(topic) + "): the message encoding is empty (ROS 2: \"cdr\")");
  }
  if (schema_id > schemas_.size()) {
    throw Error("McapWriter::registerChannel(" + quoted(topic) + "): schema id " + std::to_string(schema_id) +
                " is not registered (" + std::to_string(schemas_.size()) + " schemas)");
  }
  if (channels_.size() >= options_.max_channels) {
    throw Error("McapWriter::registerChannel(" + quoted(topic) +
                "): max_channels = " + std::to_string(options_.max_channels) + " channels are registered already");
  }
  ChannelInfo channel;
  channel.id = static_cast<std::uint16_t>(channels_.size() + 1);
  channel.schema_id = schema_id;
  channel.topic = topic;
  channel.message_encoding = message_encoding;
  channel.metadata = metadata;
  scratch_->clear();
  detail::appendChannel(*scratch_, channel);
  if (!sink_->write(scratch_->bytes(), "Channel record " + quoted(topic))) return kNoId;
  channels_.push_back(std::move(channel));
  return channels_.back().id;
}

std::span<std::uint8_t> McapWriter::reserveMessage(std::size_t max_bytes) {
  reservation_open_ = false;
  if (!isOpen() || failed()) return {};
  if (max_bytes > options_.max_message_bytes) {
    if (countRejection()) {
      first_rejection_ = "reserveMessage(" + std::to_string(max_bytes) +
                         " bytes): more than max_message_bytes = " + std::to_string(options_.max_message_bytes);
    }
    return {};
  }
  if (!chunk_->fits(max_bytes) && !writeChunk()) return {};
  reservation_open_ = true;
  reservation_bytes_ = max_bytes;
  return chunk_->reserve(max_bytes);
}

bool McapWriter::commitMessage(std::uint16_t channel_id, std::uint32_t sequence, std::int64_t log_time_ns,
                               std::int64_t publish_time_ns, std::size_t bytes_used) {
  if (!isOpen() || failed()) return false;
  const bool reserved = reservation_open_;
  reservation_open_ = false;
  if (!reserved) {
    if (countRejection()) {
      first_rejection_ = "commitMessage(channel " + std::to_string(channel_id) + ", sequence " +
                         std::to_string(sequence) + "): no space was reserved (call reserveMessage first)";
    }
    return false;
  }
  if (bytes_used > reservation_bytes_) {
    if (countRejection()) {
      first_rejection_ = "commitMessage(channel " + std::to_string(channel_id) + ", sequence " +
                         std::to_string(sequence) + "): " + std::to_string(bytes_used) + " bytes used of " +
                         std::to_string(reservation_bytes_) + " reserved";
    }
    return false;
  }
  if (channel_id == kNoId || channel_id > channels_.size()) {
    if (countRejection()) {
      first_rejection_ = "commitMessage(channel " + std::to_string(channel_id) + ", sequence " +
                         std::to_string(sequence) + "): channel " + std::to_string(channel_id) +
                         " is not registered (" + std::to_string(channels_.size()) + " channels)";
    }
    return false;
  }
  if (log_time_ns < 0 || publish_time_ns < 0) {
    if (countRejection()) {
      first_rejection_ = "commitMessage(" + channels_[channel_id - 1].topic + ", sequence " + std::to_string(sequence) +
                         "): negative time (log_time " + std::to_string(log_time_ns) + " ns, publish_time " +
                         std::to_string(publish_time_ns) + " ns)";
    }
    return false;
  }
  chunk_->commit(channel_id, sequence, log_time_ns, publish_time_ns, bytes_used);
  if (chunk_->recordsBytes() >= options_.chunk_target_bytes || chunk_->indexFull()) return writeChunk();
  return true;
}

bool McapWriter::write(std::uint16_t channel_id, std::uint32_t sequence, std::int64_t log_time_ns,
                       std::int64_t publish_time_ns, std::span<const std::uint8_t> data) {
  const std::span<std::uint8_t> space = reserveMessage(data.size());
  if (space.size() != data.size()) return false;
  if (!data.empty()) std::memcpy(space.data(), data.data(), data.size());
  return commitMessage(channel_id, sequence, log_time_ns, publish_time_ns, data.size());
}

bool McapWriter::flushIfDue(std::int64_t now_ns) {
  if (!isOpen() || failed()) return false;
  // A reservation points into the chunk buffer: the chunk it belongs to is written after its commit.
  if (chunk_->empty() || reservation_open_) return true;
  if (now_ns - chunk_->firstLogTimeNs() < options_.chunk_flush_ns) return true;
  return writeChunk();
}

bool McapWriter::flush() {
  if (!isOpen() || failed()) return false;
  reservation_open_ = false;
  return chunk_->empty() || writeChunk();
}

bool McapWriter::writeChunk() {
  reservation_open_ = false;
  if (chunk_->empty()) return true;
  const std::uint64_t chunk_offset = sink_->offset();
  if (!sink_->write(chunk_->finishChunkRecord(), "Chunk record")) return false;

  // The chunk is in the file: a reader finds its messages even if what follows fails.
  detail::ChunkIndexEntry entry;
  entry.chunk = chunk_->info(chunk_offset);
  entry.first_channel_offset = channel_offsets_.size();
  ++chunks_written_;
  messages_written_ += chunk_->messageCount();
  message_start_time_ns_ = chunks_written_ == 1 ? entry.chunk.message_start_time_ns
                                                : std::min(message_start_time_ns_, entry.chunk.message_start_time_ns);
  message_end_time_ns_ = std::max(message_end_time_ns_, entry.chunk.message_end_time_ns);

  const std::uint64_t index_offset = sink_->offset();
  const std::span<const std::uint8_t> index = chunk_->buildMessageIndex(index_offset, channel_offsets_);
  entry.channel_offset_count = channel_offsets_.size() - entry.first_channel_offset;
  entry.message_index_length = index.size();
  for (std::size_t i = entry.first_channel_offset; i < channel_offsets_.size(); ++i) {
    const std::uint16_t channel_id = channel_offsets_[i].channel_id;
    channel_message_counts_[channel_id] += chunk_->channelMessageCount(channel_id);
  }
  chunk_index_.push_back(entry);
  chunk_->clear();
  if (!sink_->write(index, "Message Index records")) return false;
  return options_.sync == SyncPolicy::kNone || sink_->sync();
}

bool McapWriter::writeAttachment(std::string_view name, std::string_view media_type, std::span<const std::uint8_t> data,
                                 std::int64_t log_time_ns, std::int64_t create_time_ns) {
  requireOpen("writeAttachment");
  if (failed()) return false;
  if (name.empty()) throw Error("McapWriter::writeAttachment: the attachment name is empty");
  if (log_time_ns < 0 || create_time_ns < 0) {
    throw Error("McapWriter::writeAttachment(" + quoted(name) + "): negative time (log_time " +
                std::to_string(log_time_ns) + " ns, create_time " + std::to_string(create_time_ns) + " ns)");
  }
  detail::AttachmentIndexEntry entry;
  entry.offset = sink_->offset();
  entry.log_time_ns = log_time_ns;
  entry.create_time_ns = create_time_ns;
  entry.data_bytes = data.size();
  entry.name = name;
  entry.media_type = media_type;

  // <opcode><length><fields up to the data length><data><crc of fields and data>
  scratch_->clear();
  const std::size_t start = scratch_->beginRecord(Opcode::kAttachment);
  detail::appendAttachmentFields(*scratch_, entry);
  const std::size_t fields_bytes = scratch_->size() - kRecordHeaderBytes;
  constexpr std::size_t kCrcBytes = 4;
  storeU64(scratch_->data() + start + kRecordLengthAt, fields_bytes + data.size() + kCrcBytes);
  entry.record_bytes = kRecordHeaderBytes + fields_bytes + data.size() + kCrcBytes;
  Crc32 crc;
  crc.update(scratch_->bytes().subspan(kRecordHeaderBytes));
  crc.update(data);
  std::uint8_t crc_field[kCrcBytes];
  storeU32(crc_field, crc.value());

  const std::string what = "Attachment " + quoted(name);
  if (!sink_->write(scratch_->bytes(), what) || !sink_->write(data, what) || !sink_->write(crc_field, what)) {
    return false;
  }
  attachments_.push_back(std::move(entry));
  return options_.sync == SyncPolicy::kNone || sink_->sync();
}

bool McapWriter::close() {
  if (!isOpen()) return !failed();
  reservation_open_ = false;
  if (!failed() && writeChunk()) {
    detail::SummaryContent summary;
    summary.schemas = schemas_;
    summary.channels = channels_;
    summary.chunks = chunk_index_;
    summary.channel_offsets = channel_offsets_;
    summary.attachments = attachments_;
    McapStatistics& statistics = summary.statistics;
    statistics.message_count = messages_written_;
    statistics.schema_count = static_cast<std::uint16_t>(schemas_.size());
    statistics.channel_count = static_cast<std::uint32_t>(channels_.size());
    statistics.attachment_count = static_cast<std::uint32_t>(attachments_.size());
    statistics.chunk_count = static_cast<std::uint32_t>(chunks_written_);
    statistics.message_start_time_ns = message_start_time_ns_;
    statistics.message_end_time_ns = message_end_time_ns_;
    for (const ChannelInfo& channel : channels_) {
      statistics.channel_message_counts[channel.id] = channel_message_counts_[channel.id];
    }
    scratch_->clear();
    detail::appendDataEndToMagic(*scratch_, sink_->offset(), summary);
    if (sink_->write(scratch_->bytes(), "summary and Footer") && options_.sync != SyncPolicy::kNone) sink_->sync();
  }
  return sink_->close();
}

bool McapWriter::countRejection() { return messages_rejected_++ == 0; }

}  // namespace vifusion::mcap
