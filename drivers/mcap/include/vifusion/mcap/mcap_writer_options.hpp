#pragma once
// Settings of McapWriter (mcap_writer.hpp), each defined once, with the range validate() enforces. The
// buffers the writer sizes from them at construction are all it uses afterwards: chunk buffer
// chunk_target_bytes + max_message_bytes, index buffers from max_messages_per_chunk and max_channels.

#include <cstddef>
#include <cstdint>
#include <string>

#include "vifusion/core/time.hpp"
#include "vifusion/mcap/mcap_format.hpp"

namespace vifusion::mcap {

inline constexpr std::size_t kKiB = 1024;
inline constexpr std::size_t kMiB = 1024 * kKiB;

/// When written chunks are forced to the storage device.
enum class SyncPolicy {
  /// write() only. A chunk that write() returned for is in the kernel's page cache: it survives the
  /// recording process being killed (SIGKILL, a crash), but not power loss or a kernel panic, which
  /// lose whatever the kernel had not yet written back (up to ~30 s with Linux's default dirty expiry).
  kNone,
  /// write() then fdatasync() after each chunk: a chunk is on the device before the next one starts, so
  /// power loss costs at most the chunk being filled (chunk_flush_ns of data). One flush per chunk, i.e.
  /// about 20 per second at the 50 ms default: small next to 30 MB/s of images, and fdatasync skips the
  /// metadata-only updates (mtime) that fsync would also flush.
  kFdatasyncPerChunk,
};

struct McapWriterOptions {
  /// A chunk is written once its records reach this size [bytes], [1, kMaxChunkTargetBytes]. 4 MiB holds
  /// two or three 640x480 depth + colour pairs: large enough for few, efficient writes, small enough that
  /// a reader loads one chunk at a time.
  std::size_t chunk_target_bytes = 4 * kMiB;
  /// A chunk is also written when it is this old [ns], (0, kMaxChunkFlushNs], measured by flushIfDue(now)
  /// from its first message's log time: what a kill or a power loss can cost at most, plus the caller's
  /// wake-up and the write. 50 ms keeps a recorder's worst loss within 100 ms (recorder.hpp says how).
  std::int64_t chunk_flush_ns = 50 * kNsPerMillisecond;
  /// Largest data of a single message [bytes], [1, kMaxMessageBytes]; reserveMessage() refuses more.
  /// 2 MiB: a 1280x720 RGB image (2.6 MB) needs more, a 640x480 one (0.9 MB) fits twice.
  std::size_t max_message_bytes = 2 * kMiB;
  /// Messages one chunk may hold, [1, kMaxMessagesPerChunk]: sizes the message index buffers; a full
  /// index closes the chunk early. 8192 is 40 s of 200 Hz IMU samples, far beyond chunk_flush_ns.
  std::size_t max_messages_per_chunk = 8192;
  /// Channels (and, separately, schemas) one file may register, [1, kMaxChannels].
  std::size_t max_channels = 64;
  /// Chunk index entries reserved at open() [chunks], [1, kMaxReservedChunks]: the summary needs one per
  /// chunk. 72 000 is one hour of 50 ms chunks: ~14 MB (64 bytes per chunk and 16 per channel in it,
  /// reserved for 8 channels). Beyond it the table grows by doubling, the only allocation after open(),
  /// once per doubling when a chunk closes.
  std::size_t reserved_chunks = 72'000;
  SyncPolicy sync = SyncPolicy::kFdatasyncPerChunk;
  /// Header.profile: "ros2" says messages are CDR and schemas ros2msg/ros2idl, as `ros2 bag` expects.
  std::string profile{kProfileRos2};
  /// Header.library: who wrote the file, for debugging.
  std::string library = "vifusion";

  static constexpr std::size_t kMaxChunkTargetBytes = 1024 * kMiB;
  static constexpr std::int64_t kMaxChunkFlushNs = 60 * kNsPerSecond;
  static constexpr std::size_t kMaxMessageBytes = 1024 * kMiB;
  static constexpr std::size_t kMaxMessagesPerChunk = 1 << 20;
  static constexpr std::size_t kMaxChannels = 65535;  ///< channel and schema ids are u16, schema id 0 is "none"
  static constexpr std::size_t kMaxReservedChunks = 10'000'000;

  /// @throws vifusion::Error naming the first bad field, its value and the allowed range.
  void validate() const;
};

}  // namespace vifusion::mcap
