#pragma once
// A small JSON text builder for the fixture writer's expected values (tests only: it allocates freely).
// Numbers that JavaScript reads exactly (everything up to 32 bits, doubles printed with 17 digits) are JSON
// numbers; 64-bit integers are decimal strings, which is how decode_cdr.mjs prints the BigInts Foxglove's
// reader returns, so they compare exactly.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace vifusion::ros2_msgs::test {

class JsonWriter {
 public:
  JsonWriter& beginObject();
  JsonWriter& endObject();
  JsonWriter& beginArray();
  JsonWriter& endArray();
  /// The key of the next value inside an object.
  JsonWriter& key(std::string_view name);

  JsonWriter& number(double value);
  JsonWriter& integer(std::int64_t value);  ///< |value| < 2^53 only
  JsonWriter& bigInteger(std::int64_t value);
  JsonWriter& bigUnsigned(std::uint64_t value);
  JsonWriter& boolean(bool value);
  JsonWriter& string(std::string_view text);

  const std::string& text() const { return text_; }

 private:
  /// A comma before every value but the first of its container (none after a key).
  void separate();

  std::string text_;
  std::vector<bool> first_in_container_;
  bool after_key_ = false;
};

}  // namespace vifusion::ros2_msgs::test
