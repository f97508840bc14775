#include "vifusion/ros2_msgs/cdr_reader.hpp"

#include <cstdio>
#include <cstring>

#include "vifusion/core/error.hpp"

namespace vifusion::ros2_msgs {
namespace {

/// Representation identifier of plain little-endian CDR, bytes 0-1 of the encapsulation header.
constexpr std::uint8_t kCdrLeIdentifierHigh = 0x00;
constexpr std::uint8_t kCdrLeIdentifierLow = 0x01;

std::string hexByte(std::uint8_t value) {
  char text[3];
  std::snprintf(text, sizeof(text), "%02x", static_cast<unsigned>(value));
  return text;
}

}  // namespace

CdrReader::CdrReader(std::span<const std::uint8_t> bytes, std::string_view type_name)
    : bytes_(bytes), type_name_(type_name) {
  if (bytes_.size() < kEncapsulationHeaderBytes) {
    fail("", "the message is " + std::to_string(bytes_.size()) + " bytes, shorter than the " +
                 std::to_string(kEncapsulationHeaderBytes) + "-byte encapsulation header");
  }
  if (bytes_[0] != kCdrLeIdentifierHigh || bytes_[1] != kCdrLeIdentifierLow) {
    fail("", "encapsulation " + hexByte(bytes_[0]) + " " + hexByte(bytes_[1]) +
                 " is not read: only 00 01 (CDR_LE, plain little-endian CDR as ROS 2 writes it) is");
  }
  // Bytes 2-3 are options; plain CDR leaves them 0 and nothing in them changes how fields are read.
  offset_ = kEncapsulationHeaderBytes;
}

CdrReader::FieldScope::FieldScope(CdrReader& reader, std::string_view name) : FieldScope(reader, name, kNoIndex) {}

CdrReader::FieldScope::FieldScope(CdrReader& reader, std::string_view name, std::size_t index) : reader_(reader) {
  if (reader_.scope_depth_ < kMaxFieldDepth) reader_.scopes_[reader_.scope_depth_] = ScopeEntry{name, index};
  ++reader_.scope_depth_;
}

CdrReader::FieldScope::~FieldScope() { --reader_.scope_depth_; }

std::string CdrReader::fieldPath(std::string_view field) const {
  std::string path;
  for (std::size_t depth = 0; depth < scope_depth_; ++depth) {
    if (!path.empty()) path += '.';
    if (depth >= kMaxFieldDepth) {
      path += "…";
      break;
    }
    path += scopes_[depth].name;
    if (scopes_[depth].index != kNoIndex) {
      // Appended piecewise: GCC 12 misreports operator+ chains of temporaries here (-Wrestrict).
      path += '[';
      path += std::to_string(scopes_[depth].index);
      path += ']';
    }
  }
  if (!field.empty()) {
    if (!path.empty()) path += '.';
    path += field;
  }
  return path.empty() ? std::string("encapsulation header") : path;
}

void CdrReader::fail(std::string_view field, std::string_view what) const { failAt(offset_, field, what); }

void CdrReader::failAt(std::size_t offset, std::string_view field, std::string_view what) const {
  throw Error(std::string(type_name_) + " field " + fieldPath(field) + " at byte " + std::to_string(offset) + ": " +
              std::string(what));
}

std::size_t CdrReader::take(std::size_t alignment, std::size_t byte_count, std::string_view field, const char* what) {
  const std::size_t body_offset = offset_ - kEncapsulationHeaderBytes;
  const std::size_t start = offset_ + (alignment - body_offset % alignment) % alignment;
  if (start > bytes_.size() || byte_count > bytes_.size() - start) {
    failAt(start, field,
           "truncated: the " + std::string(what) + " needs " + std::to_string(byte_count) +
               " bytes but the message ends at byte " + std::to_string(bytes_.size()));
  }
  offset_ = start + byte_count;
  return start;
}

template <typename T>
T CdrReader::readAligned(std::string_view field, const char* what) {
  const std::size_t start = take(sizeof(T), sizeof(T), field, what);
  T value;
  std::memcpy(&value, bytes_.data() + start, sizeof(T));
  return value;
}

bool CdrReader::readBool(std::string_view field) {
  const std::uint8_t value = readAligned<std::uint8_t>(field, "bool");
  if (value > 1) {
    failAt(offset_ - sizeof(value), field, "bool byte is " + std::to_string(value) + ", not 0 or 1");
  }
  return value == 1;
}

std::uint8_t CdrReader::readUint8(std::string_view field) { return readAligned<std::uint8_t>(field, "uint8"); }
std::int32_t CdrReader::readInt32(std::string_view field) { return readAligned<std::int32_t>(field, "int32"); }
std::uint32_t CdrReader::readUint32(std::string_view field) { return readAligned<std::uint32_t>(field, "uint32"); }
std::int64_t CdrReader::readInt64(std::string_view field) { return readAligned<std::int64_t>(field, "int64"); }
std::uint64_t CdrReader::readUint64(std::string_view field) { return readAligned<std::uint64_t>(field, "uint64"); }
double CdrReader::readFloat64(std::string_view field) { return readAligned<double>(field, "float64"); }

std::string_view CdrReader::readString(std::string_view field) {
  const std::uint32_t length = readAligned<std::uint32_t>(field, "string length");
  const std::size_t length_offset = offset_ - sizeof(length);
  if (length > remaining()) {
    failAt(length_offset, field,
           "string length " + std::to_string(length) + " runs past the end of the message (" +
               std::to_string(bytes_.size()) + " bytes, " + std::to_string(remaining()) + " left)");
  }
  if (length == 0) return {};
  const char* text = reinterpret_cast<const char*>(bytes_.data() + offset_);
  if (text[length - 1] != '\0') {
    failAt(length_offset, field, "string of length " + std::to_string(length) + " does not end in a NUL byte");
  }
  // A NUL before the end would cut the string short for every C reader, and our writer cannot write it back.
  if (const void* nul = std::memchr(text, '\0', length - 1); nul != nullptr) {
    failAt(length_offset, field,
           "string of length " + std::to_string(length) + " holds a NUL byte at index " +
               std::to_string(static_cast<const char*>(nul) - text) + ", before its end");
  }
  offset_ += length;
  return std::string_view(text, length - 1);
}

std::size_t CdrReader::readSequenceLength(std::string_view field, std::size_t min_element_bytes, std::size_t capacity) {
  const std::uint32_t count = readAligned<std::uint32_t>(field, "sequence count");
  const std::size_t count_offset = offset_ - sizeof(count);
  // Compared by division so that a huge count cannot overflow the product.
  if (min_element_bytes > 0 && count > remaining() / min_element_bytes) {
    failAt(count_offset, field,
           "sequence count " + std::to_string(count) + " × " + std::to_string(min_element_bytes) +
               " bytes runs past the end of the message (" + std::to_string(bytes_.size()) + " bytes, " +
               std::to_string(remaining()) + " left)");
  }
  if (count > capacity) {
    failAt(count_offset, field,
           "sequence count " + std::to_string(count) + " exceeds the capacity of " + std::to_string(capacity) +
               " elements");
  }
  return count;
}

std::span<const std::uint8_t> CdrReader::readUint8Sequence(std::string_view field) {
  const std::size_t count = readSequenceLength(field, sizeof(std::uint8_t), kUnbounded);
  const std::size_t start = offset_;
  offset_ += count;
  return bytes_.subspan(start, count);
}

void CdrReader::readFloat64Array(std::span<double> out, std::string_view field) {
  if (out.empty()) return;  // no elements, no padding (as the writer)
  const std::size_t start = take(sizeof(double), out.size_bytes(), field, "float64 array");
  std::memcpy(out.data(), bytes_.data() + start, out.size_bytes());
}

std::size_t CdrReader::readFloat64Sequence(std::span<double> out, std::string_view field) {
  // An element is 8 bytes; the padding before the first one is at most 7 more, which take() checks.
  const std::size_t count = readSequenceLength(field, sizeof(double), out.size());
  readFloat64Array(out.first(count), field);
  return count;
}

}  // namespace vifusion::ros2_msgs
