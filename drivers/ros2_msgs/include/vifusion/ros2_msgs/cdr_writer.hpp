#pragma once
// Writes one CDR message (cdr_encoding.hpp) into a buffer the caller owns and sizes: the writer never
// allocates, so a recorder can serialise every frame into buffers reserved at start-up.
//
// A message that does not fit does not throw and is never written past the buffer: the writer enters a
// failed state (ok() false, overflowed() true) and keeps counting, so size() is then the number of bytes
// the message needs. Writing into an empty span is how a caller sizes a message (serializedSize() in
// message_io.hpp). A value CDR cannot carry (a string with a NUL, a sequence over 2^32 − 1 elements) or a
// message that breaks its own rules (an image whose data is not step × height bytes) also fails the
// writer, with a reason from failure().

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "vifusion/ros2_msgs/cdr_encoding.hpp"

namespace vifusion::ros2_msgs {

class CdrWriter {
 public:
  /// Starts a message in `buffer` with the CDR_LE encapsulation header. `buffer` must outlive the writer.
  explicit CdrWriter(std::span<std::uint8_t> buffer);

  void writeBool(bool value);
  void writeUint8(std::uint8_t value);
  void writeInt32(std::int32_t value);
  void writeUint32(std::uint32_t value);
  void writeInt64(std::int64_t value);
  void writeUint64(std::uint64_t value);
  void writeFloat64(double value);

  /// A ROS string: uint32 length + 1, the bytes, a NUL. `text` must hold no NUL byte (the reader on the
  /// other side would cut it there); one that does fails the writer.
  void writeString(std::string_view text);
  /// The element count of a sequence (T[]) whose elements the caller writes next.
  void writeSequenceLength(std::size_t count);
  /// uint8[]: count and bytes in one copy.
  void writeUint8Sequence(std::span<const std::uint8_t> bytes);
  /// float64[N]: the elements only (the length is part of the type).
  void writeFloat64Array(std::span<const double> values);
  /// float64[]: count, then the elements.
  void writeFloat64Sequence(std::span<const double> values);

  /// Marks the message invalid for a reason that outlives the writer (a string literal); the first
  /// failure is the one kept.
  void fail(const char* reason);

  /// True while everything fit and every value was valid: bytes() is then the complete message.
  bool ok() const { return failure_ == nullptr; }
  /// True when the message needs more bytes than the buffer has (see size()).
  bool overflowed() const { return position_ > buffer_.size(); }
  /// Why the writer failed, "" while ok().
  std::string_view failure() const { return failure_ == nullptr ? std::string_view() : std::string_view(failure_); }
  /// Bytes of the message so far, encapsulation header included, whether they fit or not [bytes].
  std::size_t size() const { return position_; }
  /// Capacity of the caller's buffer [bytes].
  std::size_t capacity() const { return buffer_.size(); }
  /// The serialised message; empty unless ok().
  std::span<const std::uint8_t> bytes() const;

  /// Starts a new message in the same buffer (header written again, failure cleared).
  void reset();

 private:
  /// Zero padding up to a multiple of `alignment` counted from the end of the encapsulation header.
  void align(std::size_t alignment);
  /// Copies `byte_count` bytes at the current position if they fit; advances the position either way.
  void put(const void* data, std::size_t byte_count);
  template <typename T>
  void writeAligned(T value);

  std::span<std::uint8_t> buffer_;
  std::size_t position_ = 0;  ///< next byte to write, counted from the buffer's start (header included)
  const char* failure_ = nullptr;
};

}  // namespace vifusion::ros2_msgs
