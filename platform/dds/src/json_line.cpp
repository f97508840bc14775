#include "json_line.hpp"

#include <charconv>
#include <cmath>

namespace vifusion::dds::detail {
namespace {

template <typename Number>
void appendNumber(std::string& text, Number number) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), number);
  text.append(buffer, result.ptr);
}

}  // namespace

void JsonLine::clear() {
  text_.clear();
  need_comma_ = false;
}

void JsonLine::separate() {
  if (need_comma_) text_ += ',';
  need_comma_ = true;
}

void JsonLine::beginObject() {
  separate();
  text_ += '{';
  need_comma_ = false;
}

void JsonLine::endObject() {
  text_ += '}';
  need_comma_ = true;
}

void JsonLine::beginArray() {
  separate();
  text_ += '[';
  need_comma_ = false;
}

void JsonLine::endArray() {
  text_ += ']';
  need_comma_ = true;
}

void JsonLine::key(std::string_view name) {
  value(name);
  text_ += ':';
  need_comma_ = false;
}

void JsonLine::value(double number) {
  separate();
  if (std::isfinite(number)) {
    appendNumber(text_, number);
  } else {
    text_ += "null";
  }
}

void JsonLine::value(float number) {
  separate();
  if (std::isfinite(number)) {
    appendNumber(text_, number);
  } else {
    text_ += "null";
  }
}

void JsonLine::value(std::int64_t number) {
  separate();
  appendNumber(text_, number);
}

void JsonLine::value(std::uint64_t number) {
  separate();
  appendNumber(text_, number);
}

void JsonLine::value(bool flag) {
  separate();
  text_ += flag ? "true" : "false";
}

void JsonLine::value(const char* text) {
  if (text == nullptr) {
    separate();
    text_ += "null";
  } else {
    value(std::string_view(text));
  }
}

void JsonLine::value(std::string_view text) {
  separate();
  text_ += '"';
  for (const char c : text) {
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
      case '\r':
        text_ += "\\r";
        break;
      case '\t':
        text_ += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          static constexpr char kHex[] = "0123456789abcdef";
          text_ += "\\u00";
          text_ += kHex[(c >> 4) & 0xF];
          text_ += kHex[c & 0xF];
        } else {
          text_ += c;
        }
    }
  }
  text_ += '"';
}

}  // namespace vifusion::dds::detail
