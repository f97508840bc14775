#include "vifusion/mcap/recover_mcap.hpp"

#include <algorithm>
#include <filesystem>
#include <map>
#include <system_error>
#include <vector>

#include "vifusion/core/error.hpp"
#include "vifusion/mcap/mcap_reader.hpp"
#include "vifusion/mcap/mcap_writer.hpp"

namespace vifusion::mcap {
namespace {

void requireWritten(bool ok, const McapWriter& writer, const std::string& path_out, const std::string& what) {
  if (ok) return;
  if (writer.failed()) throw Error("recovery: " + writer.error());
  throw Error("recovery: " + path_out + ": " + what + " refused: " + writer.firstRejection());
}

}  // namespace

RecoveryResult recoverMcap(const std::string& path_in, const std::string& path_out, McapWriterOptions options) {
  std::error_code same_error;
  if (std::filesystem::equivalent(path_in, path_out, same_error)) {
    throw Error("recovery: the output " + path_out + " is the input itself; write the recovered file elsewhere");
  }
  McapReader reader(path_in);
  RecoveryResult result;
  result.note = reader.note();

  // No message is larger than the largest chunk's records.
  std::uint64_t largest_records = 0;
  for (const ChunkInfo& chunk : reader.chunks()) largest_records = std::max(largest_records, chunk.records_bytes);
  options.max_message_bytes = static_cast<std::size_t>(
      std::clamp<std::uint64_t>(largest_records, options.max_message_bytes, McapWriterOptions::kMaxMessageBytes));
  options.max_channels = std::clamp<std::size_t>(std::max(reader.channels().size(), reader.schemas().size()),
                                                 options.max_channels, McapWriterOptions::kMaxChannels);
  options.profile = reader.profile();

  McapWriter writer(options);
  requireWritten(writer.open(path_out), writer, path_out, "open");

  std::vector<SchemaInfo> schemas = reader.schemas();
  std::sort(schemas.begin(), schemas.end(), [](const SchemaInfo& a, const SchemaInfo& b) { return a.id < b.id; });
  std::map<std::uint16_t, std::uint16_t> schema_ids = {{0, 0}};
  for (const SchemaInfo& schema : schemas) {
    schema_ids[schema.id] = writer.registerSchema(schema.name, schema.encoding, schema.data);
    requireWritten(schema_ids[schema.id] != McapWriter::kNoId, writer, path_out, "schema " + schema.name);
  }
  std::vector<ChannelInfo> channels = reader.channels();
  std::sort(channels.begin(), channels.end(), [](const ChannelInfo& a, const ChannelInfo& b) { return a.id < b.id; });
  std::map<std::uint16_t, std::uint16_t> channel_ids;
  for (const ChannelInfo& channel : channels) {
    channel_ids[channel.id] = writer.registerChannel(channel.topic, schema_ids.at(channel.schema_id),
                                                     channel.message_encoding, channel.metadata);
    requireWritten(channel_ids[channel.id] != McapWriter::kNoId, writer, path_out, "channel " + channel.topic);
  }
  for (const AttachmentInfo& attachment : reader.attachments()) {
    requireWritten(writer.writeAttachment(attachment.name, attachment.media_type, attachment.data,
                                          attachment.log_time_ns, attachment.create_time_ns),
                   writer, path_out, "attachment " + attachment.name);
  }

  MessageView message;
  for (;;) {
    try {
      if (!reader.readNext(message)) break;
    } catch (const Error& e) {
      // A corrupt chunk in a file whose summary was intact: keep the others.
      ++result.chunks_skipped;
      result.note += (result.note.empty() ? "" : "; ") + std::string("skipped: ") + e.what();
      continue;
    }
    requireWritten(writer.write(channel_ids.at(message.channel_id), message.sequence, message.log_time_ns,
                                message.publish_time_ns, message.data),
                   writer, path_out, "message");
    ++result.messages;
  }
  requireWritten(writer.close(), writer, path_out, "close");

  result.chunks_read = reader.chunks().size() - result.chunks_skipped;
  result.chunks_written = writer.chunksWritten();
  result.schemas = schemas.size();
  result.channels = channels.size();
  result.attachments = reader.attachments().size();
  result.bytes_written = writer.bytesWritten();
  result.input_complete = reader.complete() && result.chunks_skipped == 0;
  return result;
}

}  // namespace vifusion::mcap
