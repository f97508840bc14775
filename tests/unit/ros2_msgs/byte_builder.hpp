#pragma once
// Builds expected CDR bytes by hand, field by field, with the padding written out explicitly, so a layout
// test states the documented layout (cdr_encoding.hpp) instead of re-running the writer's own rules.

#include <cstdint>
#include <cstring>
#include <string_view>
#include <vector>

namespace vifusion::ros2_msgs::test {

class ByteBuilder {
 public:
  ByteBuilder& raw(std::initializer_list<std::uint8_t> values) {
    bytes_.insert(bytes_.end(), values);
    return *this;
  }
  ByteBuilder& zeros(std::size_t count) {
    bytes_.insert(bytes_.end(), count, 0);
    return *this;
  }
  ByteBuilder& u8(std::uint8_t value) { return little(value); }
  ByteBuilder& i32(std::int32_t value) { return little(value); }
  ByteBuilder& u32(std::uint32_t value) { return little(value); }
  ByteBuilder& i64(std::int64_t value) { return little(value); }
  ByteBuilder& u64(std::uint64_t value) { return little(value); }
  ByteBuilder& f64(double value) { return little(value); }
  /// The characters and the NUL only; the caller writes the length (u32) and any padding itself.
  ByteBuilder& chars(std::string_view text) {
    bytes_.insert(bytes_.end(), text.begin(), text.end());
    bytes_.push_back(0);
    return *this;
  }

  std::size_t size() const { return bytes_.size(); }
  const std::vector<std::uint8_t>& bytes() const { return bytes_; }

 private:
  /// Appends `value`'s bytes in memory order: little-endian on every host the library builds for (it
  /// static_asserts so); the Header layout test spells its bytes out instead.
  template <typename T>
  ByteBuilder& little(T value) {
    std::uint8_t raw_bytes[sizeof(T)];
    std::memcpy(raw_bytes, &value, sizeof(T));
    bytes_.insert(bytes_.end(), raw_bytes, raw_bytes + sizeof(T));
    return *this;
  }

  std::vector<std::uint8_t> bytes_;
};

}  // namespace vifusion::ros2_msgs::test
