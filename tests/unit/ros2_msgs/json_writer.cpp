#include "json_writer.hpp"

#include <cassert>
#include <cmath>
#include <cstdio>

namespace vifusion::ros2_msgs::test {
namespace {

/// Largest integer a JavaScript number holds exactly.
constexpr std::int64_t kMaxSafeInteger = (std::int64_t{1} << 53) - 1;

}  // namespace

void JsonWriter::separate() {
  if (after_key_) {
    after_key_ = false;
    return;
  }
  if (!first_in_container_.empty()) {
    if (!first_in_container_.back()) text_ += ',';
    first_in_container_.back() = false;
  }
}

JsonWriter& JsonWriter::beginObject() {
  separate();
  text_ += '{';
  first_in_container_.push_back(true);
  return *this;
}

JsonWriter& JsonWriter::endObject() {
  first_in_container_.pop_back();
  text_ += '}';
  return *this;
}

JsonWriter& JsonWriter::beginArray() {
  separate();
  text_ += '[';
  first_in_container_.push_back(true);
  return *this;
}

JsonWriter& JsonWriter::endArray() {
  first_in_container_.pop_back();
  text_ += ']';
  return *this;
}

JsonWriter& JsonWriter::key(std::string_view name) {
  string(name);
  text_ += ':';
  after_key_ = true;
  return *this;
}

JsonWriter& JsonWriter::number(double value) {
  assert(std::isfinite(value));
  separate();
  char digits[32];
  std::snprintf(digits, sizeof(digits), "%.17g", value);  // 17 significant digits identify a double
  text_ += digits;
  return *this;
}

JsonWriter& JsonWriter::integer(std::int64_t value) {
  assert(value <= kMaxSafeInteger && value >= -kMaxSafeInteger);
  separate();
  text_ += std::to_string(value);
  return *this;
}

JsonWriter& JsonWriter::bigInteger(std::int64_t value) {
  separate();
  text_ += '"' + std::to_string(value) + '"';
  return *this;
}

JsonWriter& JsonWriter::bigUnsigned(std::uint64_t value) {
  separate();
  text_ += '"' + std::to_string(value) + '"';
  return *this;
}

JsonWriter& JsonWriter::boolean(bool value) {
  separate();
  text_ += value ? "true" : "false";
  return *this;
}

JsonWriter& JsonWriter::string(std::string_view text) {
  separate();
  text_ += '"';
  for (char c : text) {
    switch (c) {
      case '"':
        text_ += "\\\"";
        break;
      case '\\':
        text_ += "\\\\";
        break;
      case '\n':
        text_ += "\\n";
        break;
      case '\t':
        text_ += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char escaped[8];
          std::snprintf(escaped, sizeof(escaped), "\\u%04x", static_cast<unsigned>(c));
          text_ += escaped;
        } else {
          text_ += c;
        }
    }
  }
  text_ += '"';
  return *this;
}

}  // namespace vifusion::ros2_msgs::test
