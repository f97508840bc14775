#pragma once
// McapReader: reads an MCAP file (https://mcap.dev/spec) whole or cut. A complete file is read through its
// summary (Footer, then the Schema, Channel, Chunk Index, Attachment Index and Statistics records). A file
// without a usable summary — cut by SIGKILL, power loss or a full disk, or with a damaged summary — is
// scanned record by record from the Header: every complete, well-formed chunk whose CRC-32 matches is
// accepted, and the scan stops at the first incomplete or corrupt record, which note() names (offset and
// why). Messages then come out in file order, chunk by chunk.
//
// Corrupt input never crashes it: lengths are checked against the file before anything is read or
// allocated, and every problem is a vifusion::Error or a note naming the file, the offset and the field.
//
//   McapReader reader("run.mcap");
//   if (!reader.note().empty()) log(reader.note());     // cut: where and why the data stops
//   for (MessageView m; reader.readNext(m);) use(reader.channel(m.channel_id)->topic, m);

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "vifusion/mcap/byte_source.hpp"
#include "vifusion/mcap/mcap_records.hpp"

namespace vifusion::mcap {

namespace detail {
struct RecordingContents;
}  // namespace detail

class McapReader {
 public:
  /// Opens a file. @throws vifusion::Error when it cannot be read or is not MCAP (no magic, bad Header).
  explicit McapReader(const std::string& path);
  /// Reads from any source (memory for tests and fuzzing). @throws vifusion::Error as above.
  explicit McapReader(std::unique_ptr<ByteSource> source);
  McapReader(McapReader&&) noexcept;
  McapReader& operator=(McapReader&&) noexcept;
  ~McapReader();

  /// Header fields: "ros2" and "vifusion" for vifusion's recordings.
  const std::string& profile() const;
  const std::string& library() const;

  /// True when the summary was used (the file was closed properly).
  bool summaryUsed() const;
  /// Why the summary was not used ("the file does not end with the MCAP magic"); empty when it was.
  const std::string& summaryProblem() const;
  /// True when all of the file's data was accepted: the summary was used, or the scan reached DataEnd.
  bool complete() const { return note().empty(); }
  /// Where and why the scan stopped before the end of the data ("run.mcap: data accepted up to byte
  /// 1048576 of 1050000; stopped at offset 1048576: the file ends inside a Chunk record ..."); empty when
  /// complete().
  const std::string& note() const;

  const std::vector<SchemaInfo>& schemas() const;
  const std::vector<ChannelInfo>& channels() const;
  const std::vector<AttachmentInfo>& attachments() const;
  /// The file's Statistics record, or for a scanned file the counts over what was accepted.
  const McapStatistics& statistics() const;
  /// The chunks that will be read, in file order.
  const std::vector<ChunkInfo>& chunks() const;
  /// nullptr when the id is not defined.
  const SchemaInfo* schema(std::uint16_t id) const;
  const ChannelInfo* channel(std::uint16_t id) const;
  /// The name messages use for the input (the file's path).
  const std::string& name() const { return source_->name(); }

  /// The next message in file order; false after the last one. The view's data is valid until the next
  /// call. @throws vifusion::Error when a chunk is corrupt (CRC mismatch, malformed records), naming the
  /// file, the chunk's offset and the field.
  bool readNext(MessageView& message);
  /// Starts again from the first message.
  void rewind();

 private:
  bool loadNextItem(MessageView& message);
  bool nextInChunk(MessageView& message);
  [[noreturn]] void failChunk(const std::string& problem);

  std::unique_ptr<ByteSource> source_;
  std::unique_ptr<detail::RecordingContents> contents_;
  std::size_t next_item_ = 0;
  std::vector<std::uint8_t> record_buffer_;  ///< the current chunk (or loose message) record
  std::span<const std::uint8_t> chunk_records_;
  std::size_t chunk_position_ = 0;
  std::uint64_t chunk_offset_ = 0;
};

}  // namespace vifusion::mcap
