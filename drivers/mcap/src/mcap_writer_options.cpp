#include "vifusion/mcap/mcap_writer_options.hpp"

#include <string>

#include "vifusion/core/error.hpp"

namespace vifusion::mcap {
namespace {

void require(bool ok, const char* field, const std::string& what) {
  if (!ok) throw Error(std::string("McapWriterOptions.") + field + " " + what);
}

template <typename T>
std::string range(T low, T high, T value, const char* unit) {
  return std::string("must be in [") + std::to_string(low) + ", " + std::to_string(high) + "]" + unit + ", got " +
         std::to_string(value);
}

}  // namespace

void McapWriterOptions::validate() const {
  require(chunk_target_bytes >= 1 && chunk_target_bytes <= kMaxChunkTargetBytes, "chunk_target_bytes",
          range<std::size_t>(1, kMaxChunkTargetBytes, chunk_target_bytes, " bytes"));
  require(chunk_flush_ns > 0 && chunk_flush_ns <= kMaxChunkFlushNs, "chunk_flush_ns",
          "must be in (0, " + std::to_string(kMaxChunkFlushNs) + "] ns, got " + std::to_string(chunk_flush_ns));
  require(max_message_bytes >= 1 && max_message_bytes <= kMaxMessageBytes, "max_message_bytes",
          range<std::size_t>(1, kMaxMessageBytes, max_message_bytes, " bytes"));
  require(max_messages_per_chunk >= 1 && max_messages_per_chunk <= kMaxMessagesPerChunk, "max_messages_per_chunk",
          range<std::size_t>(1, kMaxMessagesPerChunk, max_messages_per_chunk, ""));
  require(max_channels >= 1 && max_channels <= kMaxChannels, "max_channels",
          range<std::size_t>(1, kMaxChannels, max_channels, ""));
  require(reserved_chunks >= 1 && reserved_chunks <= kMaxReservedChunks, "reserved_chunks",
          range<std::size_t>(1, kMaxReservedChunks, reserved_chunks, ""));
  require(sync == SyncPolicy::kNone || sync == SyncPolicy::kFdatasyncPerChunk, "sync",
          "must be none or fdatasync per chunk, got " + std::to_string(static_cast<int>(sync)));
}

}  // namespace vifusion::mcap
