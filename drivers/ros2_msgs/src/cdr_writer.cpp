#include "vifusion/ros2_msgs/cdr_writer.hpp"

#include <cstring>
#include <limits>

namespace vifusion::ros2_msgs {
namespace {

constexpr const char* kOverflowReason = "the message needs more bytes than the buffer holds";
constexpr const char* kNulInStringReason = "a string holds a NUL byte, which CDR strings cannot carry";
constexpr const char* kSequenceTooLongReason = "a sequence or string is longer than 2^32 - 1 elements";
constexpr std::size_t kMaxCdrLength = std::numeric_limits<std::uint32_t>::max();

}  // namespace

CdrWriter::CdrWriter(std::span<std::uint8_t> buffer) : buffer_(buffer) { reset(); }

void CdrWriter::reset() {
  position_ = 0;
  failure_ = nullptr;
  put(kCdrLittleEndianHeader.data(), kCdrLittleEndianHeader.size());
}

void CdrWriter::fail(const char* reason) {
  if (failure_ == nullptr) failure_ = reason;
}

std::span<const std::uint8_t> CdrWriter::bytes() const {
  if (!ok()) return {};
  return std::span<const std::uint8_t>(buffer_.data(), position_);
}

void CdrWriter::put(const void* data, std::size_t byte_count) {
  if (!overflowed() && byte_count <= buffer_.size() - position_) {
    if (byte_count > 0) std::memcpy(buffer_.data() + position_, data, byte_count);
  } else {
    fail(kOverflowReason);
  }
  position_ += byte_count;
}

void CdrWriter::align(std::size_t alignment) {
  static constexpr std::uint8_t kZeros[kMaxPrimitiveAlignment] = {};
  const std::size_t body_offset = position_ - kEncapsulationHeaderBytes;
  const std::size_t padding = (alignment - body_offset % alignment) % alignment;
  put(kZeros, padding);
}

template <typename T>
void CdrWriter::writeAligned(T value) {
  align(sizeof(T));
  put(&value, sizeof(T));
}

void CdrWriter::writeBool(bool value) { writeUint8(value ? 1 : 0); }
void CdrWriter::writeUint8(std::uint8_t value) { put(&value, sizeof(value)); }
void CdrWriter::writeInt32(std::int32_t value) { writeAligned(value); }
void CdrWriter::writeUint32(std::uint32_t value) { writeAligned(value); }
void CdrWriter::writeInt64(std::int64_t value) { writeAligned(value); }
void CdrWriter::writeUint64(std::uint64_t value) { writeAligned(value); }
void CdrWriter::writeFloat64(double value) { writeAligned(value); }

void CdrWriter::writeSequenceLength(std::size_t count) {
  if (count > kMaxCdrLength) {
    fail(kSequenceTooLongReason);
    return;
  }
  writeUint32(static_cast<std::uint32_t>(count));
}

void CdrWriter::writeString(std::string_view text) {
  if (text.find('\0') != std::string_view::npos) fail(kNulInStringReason);
  if (text.size() >= kMaxCdrLength) {
    fail(kSequenceTooLongReason);
    return;
  }
  writeUint32(static_cast<std::uint32_t>(text.size() + 1));
  put(text.data(), text.size());
  writeUint8(0);
}

void CdrWriter::writeUint8Sequence(std::span<const std::uint8_t> bytes) {
  writeSequenceLength(bytes.size());
  put(bytes.data(), bytes.size());
}

void CdrWriter::writeFloat64Array(std::span<const double> values) {
  // No elements, no padding (what Fast-CDR and Foxglove's reader do). Otherwise eight-byte elements keep
  // the alignment, so one alignment and one copy cover the whole array.
  if (values.empty()) return;
  align(sizeof(double));
  put(values.data(), values.size_bytes());
}

void CdrWriter::writeFloat64Sequence(std::span<const double> values) {
  writeSequenceLength(values.size());
  writeFloat64Array(values);
}

}  // namespace vifusion::ros2_msgs
