#include "text_fields.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion::datasets::detail {
namespace {

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

std::string_view trim(std::string_view text) {
  while (!text.empty() && isBlank(text.front())) text.remove_prefix(1);
  while (!text.empty() && isBlank(text.back())) text.remove_suffix(1);
  return text;
}

}  // namespace

std::string readTextFile(const std::filesystem::path& path, const std::string& display_name) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw Error(display_name + ": cannot open file '" + path.string() + "'");
  std::ostringstream contents;
  contents << file.rdbuf();
  if (file.bad()) throw Error(display_name + ": cannot read file '" + path.string() + "'");
  return contents.str();
}

std::vector<std::string_view> splitWhitespace(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t pos = 0;
  const auto separator = [](char c) { return isBlank(c) || c == ','; };
  while (pos < line.size()) {
    while (pos < line.size() && separator(line[pos])) ++pos;
    const std::size_t begin = pos;
    while (pos < line.size() && !separator(line[pos])) ++pos;
    if (pos > begin) fields.push_back(line.substr(begin, pos - begin));
  }
  return fields;
}

std::vector<std::string_view> splitCsv(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t begin = 0;
  while (true) {
    const std::size_t comma = line.find(',', begin);
    fields.push_back(
        trim(line.substr(begin, comma == std::string_view::npos ? std::string_view::npos : comma - begin)));
    if (comma == std::string_view::npos) break;
    begin = comma + 1;
  }
  return fields;
}

void forEachLine(std::string_view text, const std::function<void(std::size_t, std::string_view)>& visit) {
  std::size_t line_number = 0;
  std::size_t begin = 0;
  while (begin < text.size()) {
    std::size_t end = text.find('\n', begin);
    if (end == std::string_view::npos) end = text.size();
    visit(++line_number, text.substr(begin, end - begin));
    begin = end + 1;
  }
}

bool isCommentOrBlank(std::string_view line) {
  const std::string_view trimmed = trim(line);
  return trimmed.empty() || trimmed.front() == '#';
}

std::string where(const std::string& file, std::size_t line_number) {
  return file + " line " + std::to_string(line_number) + ": ";
}

std::int64_t parseSecondsToNs(std::string_view text, const std::string& prefix, std::string_view name) {
  if (const auto exact = decimalSecondsToNs(text)) return *exact;
  double t_s = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), t_s);
  // Negative stamps are refused: every dataset time base here starts at or after zero.
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(t_s) || t_s < 0.0 ||
      t_s > nsToSeconds(kMaxFileStampNs)) {
    throw Error(prefix + "field '" + std::string(name) + "' is not a timestamp in seconds between 0 and " +
                std::to_string(kMaxFileStampNs / kNsPerSecond) + ": '" + std::string(text) + "'");
  }
  return std::min(secondsToNs(t_s), kMaxFileStampNs);
}

std::int64_t parseStampNs(std::string_view text, const std::string& prefix, std::string_view name) {
  const std::int64_t t_ns = parseInt64(text, prefix, name);
  if (t_ns < 0 || t_ns > kMaxFileStampNs) {
    throw Error(prefix + "column '" + std::string(name) + "' is not a timestamp in nanoseconds between 0 and " +
                std::to_string(kMaxFileStampNs) + ": '" + std::string(text) + "'");
  }
  return t_ns;
}

std::int64_t parseInt64(std::string_view text, const std::string& prefix, std::string_view name) {
  std::int64_t value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size()) {
    throw Error(prefix + "column '" + std::string(name) + "' is not an integer: '" + std::string(text) + "'");
  }
  return value;
}

double parseFinite(std::string_view text, const std::string& prefix, std::string_view name) {
  double value = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || std::isnan(value)) {
    throw Error(prefix + "column '" + std::string(name) + "' is not a number: '" + std::string(text) + "'");
  }
  if (!std::isfinite(value)) {
    throw Error(prefix + "column '" + std::string(name) + "' is not finite: '" + std::string(text) + "'");
  }
  return value;
}

std::string formatMs(std::int64_t dt_ns) {
  std::ostringstream out;
  out << static_cast<double>(dt_ns) / static_cast<double>(kNsPerMillisecond) << " ms";
  return out.str();
}

void requireIncreasing(std::int64_t previous_t_ns, std::int64_t t_ns, const std::string& prefix) {
  if (t_ns < previous_t_ns) throw Error(prefix + "timestamp goes backwards by " + formatMs(previous_t_ns - t_ns));
  if (t_ns == previous_t_ns) throw Error(prefix + "timestamp repeats the previous one");
}

}  // namespace vifusion::datasets::detail
