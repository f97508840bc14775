#include "vifusion/mapfile/map_file_writer.hpp"

#include <algorithm>
#include <bit>
#include <cstring>

#include "vifusion/core/crc32.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/core/little_endian.hpp"

namespace vifusion::mapfile {
namespace {

constexpr std::size_t kLargestField = 8;  ///< bytes of the widest put*() field

std::array<std::uint8_t, kFileHeaderBytes> fileHeader() {
  std::array<std::uint8_t, kFileHeaderBytes> header{};
  std::memcpy(header.data(), kMagic.data(), kMagic.size());
  storeU32(header.data() + 8, kFormatVersion);
  storeU32(header.data() + 12, crc32(std::span<const std::uint8_t>(header.data(), 12)));
  return header;
}

std::array<std::uint8_t, kSectionHeaderBytes> sectionHeader(MapSection section, std::uint64_t payload_bytes,
                                                            std::uint32_t payload_crc) {
  std::array<std::uint8_t, kSectionHeaderBytes> header{};
  const std::string_view name = sectionName(section);
  std::memcpy(header.data(), name.data(), name.size());
  storeU64(header.data() + 8, payload_bytes);
  storeU32(header.data() + 16, payload_crc);
  storeU32(header.data() + 20, crc32(std::span<const std::uint8_t>(header.data(), 20)));
  return header;
}

}  // namespace

MapFileWriter::MapFileWriter(std::string path, std::size_t buffer_bytes) : path_(std::move(path)), file_(path_) {
  if (buffer_bytes < kSectionHeaderBytes) fail("the write buffer must hold at least a section header");
  buffer_.reserve(buffer_bytes);
  const auto header = fileHeader();
  reserve(header.size());
  buffer_.insert(buffer_.end(), header.begin(), header.end());
}

MapFileWriter::~MapFileWriter() = default;

void MapFileWriter::beginSection(MapSection section) {
  if (in_section_) fail("section '" + std::string(sectionName(section)) + "' begun inside another");
  if (static_cast<int>(section) != next_section_ || section == MapSection::kEnd)
    fail("section '" + std::string(sectionName(section)) + "' out of order");
  reserve(kSectionHeaderBytes);
  section_header_offset_ = offset_ + buffer_.size();
  buffer_.resize(buffer_.size() + kSectionHeaderBytes);  // filled in by endSection()
  in_section_ = true;
  section_bytes_ = 0;
  section_crc_.reset();
}

void MapFileWriter::reserve(std::size_t bytes) {
  if (buffer_.size() + bytes > buffer_.capacity()) flush();
}

void MapFileWriter::flush() {
  if (buffer_.empty()) return;
  // The payload's CRC runs over what leaves the buffer; a section header still in it is not payload.
  if (in_section_) {
    const std::uint64_t payload_start = std::max(offset_, section_header_offset_ + kSectionHeaderBytes);
    const std::size_t skip = static_cast<std::size_t>(payload_start - offset_);
    if (skip < buffer_.size()) {
      section_crc_.update(std::span<const std::uint8_t>(buffer_).subspan(skip));
    }
  }
  writeAt(offset_, buffer_);
  offset_ += buffer_.size();
  buffer_.clear();
}

void MapFileWriter::writeAt(std::uint64_t offset, std::span<const std::uint8_t> bytes) {
  try {
    file_.writeAt(offset, std::as_bytes(bytes));
  } catch (const Error& error) {
    fail(error.what());
  }
}

void MapFileWriter::putU8(std::uint8_t value) {
  reserve(kLargestField);
  buffer_.push_back(value);
  ++section_bytes_;
}

void MapFileWriter::putU32(std::uint32_t value) {
  reserve(kLargestField);
  const std::size_t at = buffer_.size();
  buffer_.resize(at + 4);
  storeU32(buffer_.data() + at, value);
  section_bytes_ += 4;
}

void MapFileWriter::putU64(std::uint64_t value) {
  reserve(kLargestField);
  const std::size_t at = buffer_.size();
  buffer_.resize(at + 8);
  storeU64(buffer_.data() + at, value);
  section_bytes_ += 8;
}

void MapFileWriter::putI32(std::int32_t value) { putU32(static_cast<std::uint32_t>(value)); }
void MapFileWriter::putI64(std::int64_t value) { putU64(static_cast<std::uint64_t>(value)); }
void MapFileWriter::putF32(float value) { putU32(std::bit_cast<std::uint32_t>(value)); }
void MapFileWriter::putF64(double value) { putU64(std::bit_cast<std::uint64_t>(value)); }

void MapFileWriter::putBytes(std::span<const std::uint8_t> bytes) {
  while (!bytes.empty()) {
    if (buffer_.size() == buffer_.capacity()) flush();
    const std::size_t n = std::min(bytes.size(), buffer_.capacity() - buffer_.size());
    buffer_.insert(buffer_.end(), bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(n));
    bytes = bytes.subspan(n);
    section_bytes_ += n;
  }
}

void MapFileWriter::putF32s(std::span<const float> values) {
  for (const float value : values) putF32(value);
}

void MapFileWriter::endSection() {
  if (!in_section_) fail("endSection() without a section");
  flush();
  const auto section = static_cast<MapSection>(next_section_);
  writeAt(section_header_offset_, sectionHeader(section, section_bytes_, section_crc_.value()));
  in_section_ = false;
  ++next_section_;
}

std::uint64_t MapFileWriter::commit() {
  if (in_section_ || next_section_ != static_cast<int>(MapSection::kEnd))
    fail("commit() before every section was written");
  const auto end = sectionHeader(MapSection::kEnd, 0, crc32({}));
  reserve(end.size());
  buffer_.insert(buffer_.end(), end.begin(), end.end());
  flush();
  try {
    file_.commit();
  } catch (const Error& error) {
    fail(error.what());
  }
  return offset_;
}

void MapFileWriter::fail(const std::string& what) const {
  const std::string section =
      in_section_ ? " (writing section '" + std::string(sectionName(static_cast<MapSection>(next_section_))) + "')"
                  : "";
  throw Error("map file " + path_ + section + ": " + what);
}

}  // namespace vifusion::mapfile
