#pragma once
// What McapReader knows about a file once it is open, filled either from the summary (summary_section.cpp)
// or by scanning the data section (data_section_scan.cpp): definitions, attachments, statistics, and the
// chunks (and loose messages) to read, in file order.

#include <cstdint>
#include <string>
#include <vector>

#include "vifusion/mcap/byte_source.hpp"
#include "vifusion/mcap/mcap_records.hpp"

namespace vifusion::mcap::detail {

/// A record readNext() will visit: a Chunk, or a Message outside chunks.
struct DataItem {
  std::uint64_t offset = 0;
  std::uint64_t record_bytes = 0;  ///< opcode and length included
  bool is_chunk = true;
};

struct RecordingContents {
  std::string profile;
  std::string library;
  std::uint64_t header_end = 0;  ///< file offset just after the Header record
  bool summary_used = false;
  std::string summary_problem;
  std::string note;
  std::vector<SchemaInfo> schemas;
  std::vector<ChannelInfo> channels;
  std::vector<AttachmentInfo> attachments;
  McapStatistics statistics;
  std::vector<ChunkInfo> chunks;
  std::vector<DataItem> items;

  /// Adds a definition; a repeated id must repeat the same definition, a channel's schema must be
  /// defined before it (or be 0). False with `problem` otherwise. Schema id 0 is ignored (the
  /// specification calls it invalid).
  bool addSchema(SchemaInfo&& schema, std::string& problem);
  bool addChannel(ChannelInfo&& channel, std::string& problem);
  const SchemaInfo* schema(std::uint16_t id) const;
  const ChannelInfo* channel(std::uint16_t id) const;
  /// Forgets definitions added after there were this many (those of a chunk that was then refused).
  void truncateDefinitions(std::size_t schema_count, std::size_t channel_count);
  /// Drops everything found so far (a summary that turned out unusable).
  void clearFound();

 private:
  std::vector<std::int32_t> schema_slot_;   ///< per schema id: index into schemas, or -1
  std::vector<std::int32_t> channel_slot_;  ///< per channel id: index into channels, or -1
};

/// Fills `contents` from the Footer and summary. False with `problem` (why the summary cannot be used)
/// when the file does not end in a Footer and magic, the summary is damaged (CRC, malformed records,
/// offsets outside the data) or indexes no chunk although the file has messages.
bool readSummary(const ByteSource& source, RecordingContents& contents, std::string& problem);

/// Fills `contents` by walking the data section from the Header on: accepts each complete, well-formed
/// record (chunks whose CRC-32 matches), stops at DataEnd or at the first incomplete or corrupt record,
/// which contents.note then names. Computes contents.statistics over what it accepted.
void scanDataSection(const ByteSource& source, RecordingContents& contents);

}  // namespace vifusion::mcap::detail
