// The reader's recovery path: walk the data section record by record from the Header, accepting what is
// complete and intact, and stop at the first record that is not, saying where and why. This is what makes
// a recording cut by SIGKILL, power loss or a full disk readable up to its last complete chunk.

#include <algorithm>
#include <vector>

#include "record_parser.hpp"
#include "recording_contents.hpp"
#include "vifusion/core/little_endian.hpp"
#include "vifusion/mcap/mcap_format.hpp"

namespace vifusion::mcap::detail {
namespace {

/// Counts over what the scan accepted, merged into the statistics when a record is accepted whole.
struct MessageCounts {
  std::uint64_t messages = 0;
  std::int64_t start_time_ns = 0;
  std::int64_t end_time_ns = 0;
  std::vector<std::pair<std::uint16_t, std::uint64_t>> per_channel;  ///< (channel, messages), in first-seen order

  void add(const MessageFields& message) {
    start_time_ns = messages == 0 ? message.log_time_ns : std::min(start_time_ns, message.log_time_ns);
    end_time_ns = messages == 0 ? message.log_time_ns : std::max(end_time_ns, message.log_time_ns);
    ++messages;
    for (auto& [channel, count] : per_channel) {
      if (channel == message.channel_id) {
        ++count;
        return;
      }
    }
    per_channel.emplace_back(message.channel_id, 1);
  }
};

void mergeInto(McapStatistics& statistics, const MessageCounts& counts) {
  if (counts.messages == 0) return;
  const bool first = statistics.message_count == 0;
  statistics.message_start_time_ns =
      first ? counts.start_time_ns : std::min(statistics.message_start_time_ns, counts.start_time_ns);
  statistics.message_end_time_ns =
      first ? counts.end_time_ns : std::max(statistics.message_end_time_ns, counts.end_time_ns);
  statistics.message_count += counts.messages;
  for (const auto& [channel, count] : counts.per_channel) statistics.channel_message_counts[channel] += count;
}

/// A message must name a channel defined before it.
bool checkMessage(std::span<const std::uint8_t> content, const RecordingContents& contents, MessageFields& message,
                  std::string& problem) {
  if (!parseMessage(content, message, problem)) return false;
  if (contents.channel(message.channel_id) == nullptr) {
    problem = "Message (sequence " + std::to_string(message.sequence) + ") on channel " +
              std::to_string(message.channel_id) + ", which is not defined before it";
    return false;
  }
  return true;
}

/// Checks a Chunk record's content whole (CRC, each inner record) and takes its definitions and counts.
/// On a problem the definitions it added are dropped again.
bool acceptChunk(std::span<const std::uint8_t> content, RecordingContents& contents, ChunkFields& chunk,
                 MessageCounts& counts, std::string& problem) {
  if (!parseChunk(content, chunk, problem)) return false;
  const std::size_t schemas_before = contents.schemas.size();
  const std::size_t channels_before = contents.channels.size();
  std::size_t position = 0;
  RawRecord record;
  bool ok = true;
  while (ok && nextRecord(chunk.records, position, record, problem)) {
    switch (static_cast<Opcode>(record.opcode)) {
      case Opcode::kSchema: {
        SchemaInfo schema;
        ok = parseSchema(record.content, schema, problem) && contents.addSchema(std::move(schema), problem);
        break;
      }
      case Opcode::kChannel: {
        ChannelInfo channel;
        ok = parseChannel(record.content, channel, problem) && contents.addChannel(std::move(channel), problem);
        break;
      }
      case Opcode::kMessage: {
        MessageFields message;
        ok = checkMessage(record.content, contents, message, problem);
        if (ok) counts.add(message);
        break;
      }
      default:
        if (record.opcode < kFirstUndefinedOpcode) {
          problem = "a " + std::string(opcodeName(record.opcode)) + " record is not allowed inside a chunk";
          ok = false;
        }
        break;
    }
    if (!ok) problem = "record at offset " + std::to_string(record.offset) + " of its records: " + problem;
  }
  if (ok && !problem.empty()) problem = "its records " + problem;  // nextRecord: an incomplete inner record
  if (ok && problem.empty()) return true;
  contents.truncateDefinitions(schemas_before, channels_before);
  return false;
}

}  // namespace

void scanDataSection(const ByteSource& source, RecordingContents& contents) {
  const std::uint64_t size = source.size();
  std::uint64_t position = contents.header_end;
  std::vector<std::uint8_t> record;
  std::string problem;
  std::string stop;  // why the scan stopped early; empty when it reached DataEnd
  McapStatistics& statistics = contents.statistics;

  for (;;) {
    const std::uint64_t left = size - position;
    if (left == 0) {
      stop = "the file ends after a complete record, without a DataEnd record";
      break;
    }
    if (left < kRecordHeaderBytes) {
      stop = "the file ends inside a record header (" + std::to_string(left) + " of " +
             std::to_string(kRecordHeaderBytes) + " bytes)";
      break;
    }
    std::uint8_t header[kRecordHeaderBytes];
    source.read(position, header);
    const std::uint8_t opcode = header[0];
    const std::uint64_t length = loadU64(header + kRecordLengthAt);
    const std::string name(opcodeName(opcode));
    if (length > left - kRecordHeaderBytes) {
      stop = "the file ends inside a " + name + " record (content of " + std::to_string(length) + " bytes, " +
             std::to_string(left - kRecordHeaderBytes) + " present)";
      break;
    }
    const std::uint64_t record_bytes = kRecordHeaderBytes + length;
    const auto readContent = [&]() -> std::span<const std::uint8_t> {
      record.resize(static_cast<std::size_t>(length));
      source.read(position + kRecordHeaderBytes, record);
      return record;
    };

    bool accepted = true;
    bool end_of_data = false;
    switch (static_cast<Opcode>(opcode)) {
      case Opcode::kSchema: {
        SchemaInfo schema;
        accepted = parseSchema(readContent(), schema, problem) && contents.addSchema(std::move(schema), problem);
        break;
      }
      case Opcode::kChannel: {
        ChannelInfo channel;
        accepted = parseChannel(readContent(), channel, problem) && contents.addChannel(std::move(channel), problem);
        break;
      }
      case Opcode::kMessage: {
        MessageFields message;
        MessageCounts counts;
        accepted = checkMessage(readContent(), contents, message, problem);
        if (accepted) {
          counts.add(message);
          mergeInto(statistics, counts);
          contents.items.push_back({position, record_bytes, false});
        }
        break;
      }
      case Opcode::kChunk: {
        ChunkFields chunk;
        MessageCounts counts;
        accepted = acceptChunk(readContent(), contents, chunk, counts, problem);
        if (accepted) {
          mergeInto(statistics, counts);
          ++statistics.chunk_count;
          contents.chunks.push_back(
              {position, record_bytes, chunk.records.size(), chunk.message_start_time_ns, chunk.message_end_time_ns});
          contents.items.push_back({position, record_bytes, true});
        }
        break;
      }
      case Opcode::kAttachment: {
        AttachmentInfo attachment;
        accepted = parseAttachment(readContent(), attachment, problem);
        if (accepted) contents.attachments.push_back(std::move(attachment));
        break;
      }
      case Opcode::kMessageIndex:
      case Opcode::kMetadata:
        break;  // indexes are rebuilt from the chunks; metadata is not used
      case Opcode::kDataEnd:
      case Opcode::kFooter:  // a file without DataEnd and summary: its data ends at the Footer
        end_of_data = true;
        break;
      default:
        if (opcode < kFirstUndefinedOpcode) {
          stop = "a " + name + " record, which is not allowed in the data section (corrupt bytes?)";
          break;
        }
        break;  // reserved and private records: skipped, as the specification asks
    }
    if (!accepted) stop = "the " + name + " record there is corrupt: " + problem;
    if (!stop.empty()) break;
    if (end_of_data) break;
    position += record_bytes;
  }

  statistics.schema_count = static_cast<std::uint16_t>(contents.schemas.size());
  statistics.channel_count = static_cast<std::uint32_t>(contents.channels.size());
  statistics.attachment_count = static_cast<std::uint32_t>(contents.attachments.size());
  if (!stop.empty()) {
    contents.note = source.name() + ": data accepted up to byte " + std::to_string(position) + " of " +
                    std::to_string(size) + " (" + std::to_string(contents.chunks.size()) + " chunks, " +
                    std::to_string(statistics.message_count) + " messages); stopped at offset " +
                    std::to_string(position) + ": " + stop;
  }
}

}  // namespace vifusion::mcap::detail
