#include "vifusion/mcap/mcap_reader.hpp"

#include <algorithm>

#include "record_parser.hpp"
#include "recording_contents.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/core/little_endian.hpp"
#include "vifusion/mcap/mcap_format.hpp"

namespace vifusion::mcap {
namespace {

/// Fills `message` from a Message record's content, which must name a defined channel.
bool decodeMessage(std::span<const std::uint8_t> content, const detail::RecordingContents& contents,
                   MessageView& message, std::string& problem) {
  detail::MessageFields fields;
  if (!detail::parseMessage(content, fields, problem)) return false;
  if (contents.channel(fields.channel_id) == nullptr) {
    problem = "Message (sequence " + std::to_string(fields.sequence) + ") on channel " +
              std::to_string(fields.channel_id) + ", which is not defined";
    return false;
  }
  message.channel_id = fields.channel_id;
  message.sequence = fields.sequence;
  message.log_time_ns = fields.log_time_ns;
  message.publish_time_ns = fields.publish_time_ns;
  message.data = fields.data;
  return true;
}

/// Reads the magic and the Header; a file cut inside the Header opens with no data and a note.
void readHeader(const ByteSource& source, detail::RecordingContents& contents) {
  const std::string& name = source.name();
  const std::uint64_t size = source.size();
  std::uint8_t magic[kMagic.size()] = {};
  const std::size_t magic_bytes = static_cast<std::size_t>(std::min<std::uint64_t>(size, kMagic.size()));
  source.read(0, std::span(magic, magic_bytes));
  if (!std::equal(magic, magic + magic_bytes, kMagic.begin())) {
    throw Error(name + ": not an MCAP file: it does not start with the MCAP magic (0x89 \"MCAP0\\r\\n\")");
  }
  if (magic_bytes < kMagic.size()) {
    throw Error(name + ": not an MCAP recording yet: the file ends inside the MCAP magic (" +
                std::to_string(magic_bytes) + " of " + std::to_string(kMagic.size()) + " bytes)");
  }
  const std::uint64_t left = size - kMagic.size();
  std::uint8_t header[kRecordHeaderBytes];
  if (left >= kRecordHeaderBytes) source.read(kMagic.size(), header);
  if (left >= kRecordHeaderBytes && header[0] != static_cast<std::uint8_t>(Opcode::kHeader)) {
    throw Error(name + ": not an MCAP file: the record after the magic is a " + std::string(opcodeName(header[0])) +
                " record, not a Header");
  }
  const std::uint64_t length = left >= kRecordHeaderBytes ? loadU64(header + kRecordLengthAt) : 0;
  if (left < kRecordHeaderBytes || length > left - kRecordHeaderBytes) {
    contents.header_end = size;
    contents.summary_problem = "the file ends inside the Header record";
    contents.note = name + ": no data: the file ends inside the Header record (" + std::to_string(size) + " bytes)";
    return;
  }
  std::vector<std::uint8_t> content(static_cast<std::size_t>(length));
  source.read(kMagic.size() + kRecordHeaderBytes, content);
  detail::HeaderFields fields;
  std::string problem;
  if (!detail::parseHeader(content, fields, problem)) throw Error(name + ": the Header record is corrupt: " + problem);
  contents.profile = std::move(fields.profile);
  contents.library = std::move(fields.library);
  contents.header_end = kMagic.size() + kRecordHeaderBytes + length;
}

}  // namespace

McapReader::McapReader(const std::string& path) : McapReader(std::make_unique<FileByteSource>(path)) {}

McapReader::McapReader(std::unique_ptr<ByteSource> source)
    : source_(std::move(source)), contents_(std::make_unique<detail::RecordingContents>()) {
  if (source_->size() == 0) throw Error(source_->name() + ": the file is empty (0 bytes): not an MCAP recording");
  readHeader(*source_, *contents_);
  if (!contents_->note.empty()) return;  // cut inside the Header: nothing more to find
  std::string problem;
  contents_->summary_used = detail::readSummary(*source_, *contents_, problem);
  if (!contents_->summary_used) {
    contents_->summary_problem = problem;
    contents_->clearFound();
    detail::scanDataSection(*source_, *contents_);
  }
  // Sized once for the largest record, so that readNext() allocates nothing.
  std::uint64_t largest = 0;
  for (const detail::DataItem& item : contents_->items) largest = std::max(largest, item.record_bytes);
  record_buffer_.reserve(static_cast<std::size_t>(largest));
}

McapReader::McapReader(McapReader&&) noexcept = default;
McapReader& McapReader::operator=(McapReader&&) noexcept = default;
McapReader::~McapReader() = default;

const std::string& McapReader::profile() const { return contents_->profile; }
const std::string& McapReader::library() const { return contents_->library; }
bool McapReader::summaryUsed() const { return contents_->summary_used; }
const std::string& McapReader::summaryProblem() const { return contents_->summary_problem; }
const std::string& McapReader::note() const { return contents_->note; }
const std::vector<SchemaInfo>& McapReader::schemas() const { return contents_->schemas; }
const std::vector<ChannelInfo>& McapReader::channels() const { return contents_->channels; }
const std::vector<AttachmentInfo>& McapReader::attachments() const { return contents_->attachments; }
const McapStatistics& McapReader::statistics() const { return contents_->statistics; }
const std::vector<ChunkInfo>& McapReader::chunks() const { return contents_->chunks; }
const SchemaInfo* McapReader::schema(std::uint16_t id) const { return contents_->schema(id); }
const ChannelInfo* McapReader::channel(std::uint16_t id) const { return contents_->channel(id); }

bool McapReader::readNext(MessageView& message) {
  for (;;) {
    if (chunk_position_ < chunk_records_.size()) {
      if (nextInChunk(message)) return true;
      continue;
    }
    if (next_item_ >= contents_->items.size()) return false;
    if (loadNextItem(message)) return true;
  }
}

void McapReader::rewind() {
  next_item_ = 0;
  chunk_records_ = {};
  chunk_position_ = 0;
}

bool McapReader::loadNextItem(MessageView& message) {
  const detail::DataItem& item = contents_->items[next_item_++];
  chunk_records_ = {};
  chunk_position_ = 0;
  chunk_offset_ = item.offset;
  record_buffer_.resize(static_cast<std::size_t>(item.record_bytes));
  source_->read(item.offset, record_buffer_);
  const std::uint8_t expected = static_cast<std::uint8_t>(item.is_chunk ? Opcode::kChunk : Opcode::kMessage);
  if (record_buffer_[0] != expected ||
      loadU64(record_buffer_.data() + kRecordLengthAt) != item.record_bytes - kRecordHeaderBytes) {
    failChunk("the index points at a " + std::string(opcodeName(record_buffer_[0])) + " record of " +
              std::to_string(loadU64(record_buffer_.data() + kRecordLengthAt)) + " bytes, not a " +
              std::string(opcodeName(expected)) + " record of " +
              std::to_string(item.record_bytes - kRecordHeaderBytes));
  }
  const std::span<const std::uint8_t> content = std::span(record_buffer_).subspan(kRecordHeaderBytes);
  std::string problem;
  if (!item.is_chunk) {
    if (!decodeMessage(content, *contents_, message, problem)) failChunk(problem);
    return true;
  }
  detail::ChunkFields chunk;
  if (!detail::parseChunk(content, chunk, problem)) failChunk(problem);
  chunk_records_ = chunk.records;
  return false;
}

bool McapReader::nextInChunk(MessageView& message) {
  detail::RawRecord record;
  std::string problem;
  if (!detail::nextRecord(chunk_records_, chunk_position_, record, problem)) {
    if (!problem.empty()) failChunk("its records " + problem);
    return false;
  }
  switch (static_cast<Opcode>(record.opcode)) {
    case Opcode::kMessage:
      if (!decodeMessage(record.content, *contents_, message, problem)) {
        failChunk("record at offset " + std::to_string(record.offset) + " of its records: " + problem);
      }
      return true;
    case Opcode::kSchema:
    case Opcode::kChannel:
      return false;  // taken when the file was opened
    default:
      if (record.opcode < kFirstUndefinedOpcode) {
        failChunk("record at offset " + std::to_string(record.offset) + " of its records: a " +
                  std::string(opcodeName(record.opcode)) + " record is not allowed inside a chunk");
      }
      return false;
  }
}

void McapReader::failChunk(const std::string& problem) {
  // The rest of this chunk is skipped: a caller that catches the error may read on from the next one.
  chunk_records_ = {};
  chunk_position_ = 0;
  throw Error(name() + ": " + (next_item_ > 0 && !contents_->items[next_item_ - 1].is_chunk ? "message" : "chunk") +
              " at offset " + std::to_string(chunk_offset_) + ": " + problem);
}

}  // namespace vifusion::mcap
