#pragma once
// Writes one JSON value on one line, for `vifusion echo`: keys in the order given, numbers in their
// shortest exact form (std::to_chars), non-finite numbers as null, strings escaped.

#include <cstdint>
#include <string>
#include <string_view>

namespace vifusion::dds::detail {

class JsonLine {
 public:
  /// Starts a new line, keeping the buffer's capacity.
  void clear();
  void beginObject();
  void endObject();
  void beginArray();
  void endArray();
  void key(std::string_view name);
  void value(double number);
  void value(float number);
  void value(std::int64_t number);
  void value(std::uint64_t number);
  void value(bool flag);
  /// A C string from a message; null prints as JSON null.
  void value(const char* text);
  void value(std::string_view text);

  const std::string& text() const { return text_; }

 private:
  void separate();

  std::string text_;
  bool need_comma_ = false;
};

}  // namespace vifusion::dds::detail
