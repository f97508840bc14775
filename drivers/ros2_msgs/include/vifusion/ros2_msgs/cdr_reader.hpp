#pragma once
// Reads one CDR message (cdr_encoding.hpp) from bytes the caller owns, without copying or allocating:
// strings and byte sequences come back as views into those bytes, valid while they live.
//
// Every read is bounds-checked. A message that is truncated, has a length or count larger than what is
// left, a bool that is neither 0 nor 1, or a value outside its type's range throws vifusion::Error naming
// the message type, the field (its path from the message root, e.g. "transforms[1].header.frame_id") and
// the byte offset counted from the start of the message (encapsulation header included), e.g.
//   "sensor_msgs/msg/Image field data at byte 48: sequence count 4294967295 × 1 bytes runs past the end
//    of the message (82 bytes, 30 left)".
// Only the error path allocates (the message text).

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "vifusion/ros2_msgs/cdr_encoding.hpp"

namespace vifusion::ros2_msgs {

class CdrReader {
 public:
  /// Checks the encapsulation header: CDR_LE only; big-endian, parameter-list and XCDR2 encodings are
  /// refused with their identifier bytes quoted.
  /// `type_name` ("sensor_msgs/msg/Imu") is quoted in every error; it must outlive the reader.
  CdrReader(std::span<const std::uint8_t> bytes, std::string_view type_name);

  bool readBool(std::string_view field);
  std::uint8_t readUint8(std::string_view field);
  std::int32_t readInt32(std::string_view field);
  std::uint32_t readUint32(std::string_view field);
  std::int64_t readInt64(std::string_view field);
  std::uint64_t readUint64(std::string_view field);
  double readFloat64(std::string_view field);

  /// A ROS string, as a view of its bytes without the NUL. Length 0 (no NUL at all) reads as "", as
  /// Fast-CDR and Foxglove's reader accept it.
  std::string_view readString(std::string_view field);
  /// readSequenceLength()'s capacity for a sequence held as a view (no fixed-capacity array behind it).
  static constexpr std::size_t kUnbounded = static_cast<std::size_t>(-1);

  /// The element count of a sequence (T[]), checked against what can still follow: `count` elements of at
  /// least `min_element_bytes` each must fit in the bytes left, and at most `capacity` are accepted (the
  /// fixed capacity of the struct that receives them).
  std::size_t readSequenceLength(std::string_view field, std::size_t min_element_bytes, std::size_t capacity);
  /// uint8[]: a view of the bytes.
  std::span<const std::uint8_t> readUint8Sequence(std::string_view field);
  /// float64[N] with N = out.size().
  void readFloat64Array(std::span<double> out, std::string_view field);
  /// float64[] into `out`; more elements than out.size() is an error. Returns the element count.
  std::size_t readFloat64Sequence(std::span<double> out, std::string_view field);

  /// Throws vifusion::Error for `field` at the current offset: "<type> field <path> at byte N: <what>".
  [[noreturn]] void fail(std::string_view field, std::string_view what) const;
  /// The same at byte `offset`, for a value found bad after it was read (its start: offset() − its size).
  [[noreturn]] void failAt(std::size_t offset, std::string_view field, std::string_view what) const;

  /// Next byte to read, counted from the start of the message (encapsulation header included).
  std::size_t offset() const { return offset_; }
  /// Bytes not read yet. CDR allows trailing bytes after the last field (padding); they are not an error.
  std::size_t remaining() const { return bytes_.size() - offset_; }
  std::string_view typeName() const { return type_name_; }

  /// While alive, names a nested field (and the element index within a sequence) in error messages:
  /// reading "sec" inside FieldScope("header") and FieldScope("stamp") reports "header.stamp.sec".
  class FieldScope {
   public:
    FieldScope(CdrReader& reader, std::string_view name);
    FieldScope(CdrReader& reader, std::string_view name, std::size_t index);
    ~FieldScope();
    FieldScope(const FieldScope&) = delete;
    FieldScope& operator=(const FieldScope&) = delete;

   private:
    CdrReader& reader_;
  };

 private:
  /// Deepest nesting an error message names in full; deeper scopes appear as "…". Our messages nest 4 deep
  /// (TFMessage.transforms[i].header.stamp).
  static constexpr std::size_t kMaxFieldDepth = 8;
  static constexpr std::size_t kNoIndex = static_cast<std::size_t>(-1);  ///< a scope that is not an element

  struct ScopeEntry {
    std::string_view name;
    std::size_t index = kNoIndex;
  };

  /// Skips padding up to `alignment` (counted from the end of the header) and checks that `byte_count`
  /// bytes follow; returns the offset of the first of them.
  std::size_t take(std::size_t alignment, std::size_t byte_count, std::string_view field, const char* what);
  template <typename T>
  T readAligned(std::string_view field, const char* what);
  std::string fieldPath(std::string_view field) const;

  std::span<const std::uint8_t> bytes_;
  std::string_view type_name_;
  std::size_t offset_ = 0;
  std::array<ScopeEntry, kMaxFieldDepth> scopes_{};
  std::size_t scope_depth_ = 0;
};

/// Reads a nested message field (one with a deserialize(CdrReader&)) with its name in the reader's error
/// paths ("header.frame_id").
template <typename Field>
void readNested(CdrReader& reader, std::string_view name, Field& field) {
  CdrReader::FieldScope scope(reader, name);
  field.deserialize(reader);
}

}  // namespace vifusion::ros2_msgs
