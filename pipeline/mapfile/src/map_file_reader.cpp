#include "vifusion/mapfile/map_file_reader.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "vifusion/core/error.hpp"
#include "vifusion/core/little_endian.hpp"

namespace vifusion::mapfile {
namespace {

std::string hex(std::uint32_t value) {
  char text[16];
  std::snprintf(text, sizeof(text), "%08x", value);
  return text;
}

/// "'surfels'". Appended piece by piece: GCC 12's -Wrestrict misfires on "'" + std::string(…).
std::string quoted(MapSection section) {
  std::string text(1, '\'');
  text += sectionName(section);
  text += '\'';
  return text;
}
std::string quoted(int section) { return quoted(static_cast<MapSection>(section)); }

}  // namespace

MapFileReader::MapFileReader(std::string path, std::size_t buffer_bytes) : path_(std::move(path)) {
  if (buffer_bytes < kSectionHeaderBytes) failFile("the read buffer must hold at least a section header");
  buffer_.reserve(buffer_bytes);
  fd_ = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) failFile(std::string("cannot be opened: ") + std::strerror(errno));
  // A constructor that throws runs no destructor: close here, or every refused file would keep its descriptor.
  try {
    readFileHeader();
  } catch (...) {
    ::close(fd_);
    fd_ = -1;
    throw;
  }
}

void MapFileReader::readFileHeader() {
  struct stat status {};
  if (::fstat(fd_, &status) != 0 || !S_ISREG(status.st_mode)) failFile("is not a regular file");
  file_bytes_ = static_cast<std::uint64_t>(status.st_size);

  std::array<std::uint8_t, kFileHeaderBytes> header{};
  if (!readAt(0, header)) failFile("is not a vifusion map file (" + std::to_string(file_bytes_) + " bytes)");
  if (!std::equal(kMagic.begin(), kMagic.end(), header.begin())) failFile("is not a vifusion map file");
  if (loadU32(header.data() + 12) != crc32(std::span<const std::uint8_t>(header.data(), 12)))
    failFile("its file header is corrupt (checksum mismatch)");
  version_ = loadU32(header.data() + 8);
  if (version_ > kFormatVersion)
    failFile("was written in map format version " + std::to_string(version_) + ", newer than this vifusion reads (" +
             std::to_string(kFormatVersion) + "): load it with a newer vifusion");
  if (version_ == 0) failFile("its file header says format version 0, which does not exist");
  offset_ = kFileHeaderBytes;
}

MapFileReader::~MapFileReader() {
  if (fd_ >= 0) ::close(fd_);
}

bool MapFileReader::readAt(std::uint64_t offset, std::span<std::uint8_t> out) const {
  while (!out.empty()) {
    const ssize_t got = ::pread(fd_, out.data(), out.size(), static_cast<off_t>(offset));
    if (got < 0) {
      if (errno == EINTR) continue;
      failFile(std::string("read failed: ") + std::strerror(errno));
    }
    if (got == 0) return false;
    out = out.subspan(static_cast<std::size_t>(got));
    offset += static_cast<std::uint64_t>(got);
  }
  return true;
}

std::uint64_t MapFileReader::beginSection(MapSection expected) {
  if (current_section_ >= 0) fail("read past its end into section " + quoted(expected));
  const std::string after = last_section_ < 0 ? "the file header" : "section " + quoted(last_section_);
  std::array<std::uint8_t, kSectionHeaderBytes> header{};
  if (!readAt(offset_, header))
    failFile("ends after " + after + ": section " + quoted(expected) + " and the rest are missing (the file was cut)");
  if (loadU32(header.data() + 20) != crc32(std::span<const std::uint8_t>(header.data(), 20)))
    failFile("the header of the section after " + after + " (at byte " + std::to_string(offset_) +
             ") is corrupt (checksum mismatch)");
  std::array<char, kSectionTagBytes> tag{};
  std::memcpy(tag.data(), header.data(), tag.size());
  const std::optional<MapSection> section = sectionFromTag(tag);
  if (!section) failFile("unknown section after " + after + " (at byte " + std::to_string(offset_) + ")");
  if (*section != expected) failFile("section " + quoted(*section) + " where section " + quoted(expected) + " belongs");
  current_section_ = static_cast<int>(expected);
  section_offset_ = offset_ + kSectionHeaderBytes;
  section_bytes_ = loadU64(header.data() + 8);
  payload_bytes_[static_cast<std::size_t>(expected)] = section_bytes_;
  section_stored_crc_ = loadU32(header.data() + 16);
  section_read_ = 0;
  section_crc_.reset();
  offset_ = section_offset_;
  buffer_.clear();
  position_ = 0;
  if (section_bytes_ > file_bytes_ - std::min(file_bytes_, section_offset_))
    fail("cut: " + std::to_string(file_bytes_ - std::min(file_bytes_, section_offset_)) + " of its " +
         std::to_string(section_bytes_) + " bytes are in the file");
  // A section that fits the buffer is read and checked whole before anything is decoded from it.
  section_checked_ = section_bytes_ <= buffer_.capacity();
  if (section_checked_) {
    need(static_cast<std::size_t>(section_bytes_));
    if (section_crc_.value() != section_stored_crc_)
      fail("corrupt (checksum " + hex(section_crc_.value()) + ", stored " + hex(section_stored_crc_) + ")");
  }
  return section_bytes_;
}

void MapFileReader::need(std::size_t bytes) {
  if (current_section_ < 0) failFile("a field read outside any section");
  if (bytes > remaining())
    fail("its fields need more bytes than its " + std::to_string(section_bytes_) + " (at payload byte " +
         std::to_string(section_read_) + ")");
  const std::size_t available = buffer_.size() - position_;
  if (available >= bytes) return;
  // Keep the unread tail, then load as much of the rest of the payload as fits.
  std::memmove(buffer_.data(), buffer_.data() + position_, available);
  buffer_.resize(available);
  position_ = 0;
  const std::uint64_t unloaded = section_offset_ + section_bytes_ - offset_;
  const std::size_t load = static_cast<std::size_t>(std::min<std::uint64_t>(unloaded, buffer_.capacity() - available));
  buffer_.resize(available + load);
  const std::span<std::uint8_t> fresh(buffer_.data() + available, load);
  if (!readAt(offset_, fresh)) fail("cut while reading it (the file shrank)");
  section_crc_.update(fresh);
  offset_ += load;
}

std::uint8_t MapFileReader::getU8() {
  need(1);
  ++section_read_;
  return buffer_[position_++];
}

std::uint32_t MapFileReader::getU32() {
  need(4);
  const std::uint32_t value = loadU32(buffer_.data() + position_);
  position_ += 4;
  section_read_ += 4;
  return value;
}

std::uint64_t MapFileReader::getU64() {
  need(8);
  const std::uint64_t value = loadU64(buffer_.data() + position_);
  position_ += 8;
  section_read_ += 8;
  return value;
}

std::int32_t MapFileReader::getI32() { return static_cast<std::int32_t>(getU32()); }
std::int64_t MapFileReader::getI64() { return static_cast<std::int64_t>(getU64()); }
float MapFileReader::getF32() { return std::bit_cast<float>(getU32()); }
double MapFileReader::getF64() { return std::bit_cast<double>(getU64()); }

void MapFileReader::getBytes(std::span<std::uint8_t> out) {
  while (!out.empty()) {
    const std::size_t n = std::min(out.size(), buffer_.capacity());
    need(n);
    std::memcpy(out.data(), buffer_.data() + position_, n);
    position_ += n;
    section_read_ += n;
    out = out.subspan(n);
  }
}

void MapFileReader::getF32s(std::span<float> out) {
  for (float& value : out) value = getF32();
}

void MapFileReader::endSection() {
  if (current_section_ < 0) failFile("endSection() outside any section");
  if (remaining() != 0)
    fail(std::to_string(remaining()) + " bytes after its last field (its layout is not this version's)");
  if (!section_checked_ && section_crc_.value() != section_stored_crc_)
    fail("corrupt (checksum " + hex(section_crc_.value()) + ", stored " + hex(section_stored_crc_) + ")");
  offset_ = section_offset_ + section_bytes_;
  last_section_ = current_section_;
  current_section_ = -1;
  buffer_.clear();
  position_ = 0;
}

void MapFileReader::skipRest() {
  while (remaining() > 0) {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(remaining(), buffer_.capacity()));
    need(n);
    position_ += n;
    section_read_ += n;
  }
  endSection();
}

void MapFileReader::finish() {
  beginSection(MapSection::kEnd);
  endSection();
  if (offset_ != file_bytes_)
    failFile(std::to_string(file_bytes_ - offset_) + " bytes follow its end section (not written by vifusion)");
}

void MapFileReader::fail(const std::string& what) const {
  const int section = current_section_ >= 0 ? current_section_ : last_section_;
  throw Error("map file " + path_ + ": section " + (section >= 0 ? quoted(section) : "(none)") + ": " + what);
}

void MapFileReader::failFile(const std::string& what) const { throw Error("map file " + path_ + ": " + what); }

}  // namespace vifusion::mapfile
