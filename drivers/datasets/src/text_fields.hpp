#pragma once
// Private helpers shared by the readers: reading text files, splitting lines, exact number and
// timestamp parsing, and the wording of the common errors so every reader reports alike.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace vifusion::datasets::detail {

/// The whole file as text. `display_name` is how errors name the file.
/// @throws vifusion::Error if it cannot be opened or read.
std::string readTextFile(const std::filesystem::path& path, const std::string& display_name);

/// Fields separated by spaces, tabs or commas (as associate.py treats TUM files); runs of
/// separators count as one, so there are no empty fields. '\r' is a separator, so CRLF files parse.
std::vector<std::string_view> splitWhitespace(std::string_view line);

/// Comma-separated fields with surrounding blanks trimmed; empty fields are kept (a missing value).
std::vector<std::string_view> splitCsv(std::string_view line);

/// Calls `visit(line_number, line)` for each line (1-based numbers, '\n' removed, '\r' kept).
void forEachLine(std::string_view text, const std::function<void(std::size_t, std::string_view)>& visit);

/// True for a line holding only blanks or starting (after blanks) with '#'.
bool isCommentOrBlank(std::string_view line);

/// "<file> line <n>: " — the prefix of every line-level error.
std::string where(const std::string& file, std::size_t line_number);

/// Decimal seconds ("1305031098.6659", "0", "12.5") to ns, exactly: digits are converted one by one,
/// because a double holds a 10-digit epoch second only to ~0.2 µs. Exponent notation is accepted
/// through a double. Stamps must lie in [0, kMaxFileStampNs].
/// @throws vifusion::Error "<prefix>field '<name>' is not a timestamp in seconds between 0 and ...".
std::int64_t parseSecondsToNs(std::string_view text, const std::string& prefix, std::string_view name);

/// An integer stamp in nanoseconds (EuRoC's first column), within [0, kMaxFileStampNs].
/// @throws vifusion::Error naming the field and the range.
std::int64_t parseStampNs(std::string_view text, const std::string& prefix, std::string_view name);

/// A decimal integer (optionally signed). @throws vifusion::Error naming the field.
std::int64_t parseInt64(std::string_view text, const std::string& prefix, std::string_view name);

/// A finite double. @throws vifusion::Error "<prefix>column '<name>' is not a number: '<text>'" (also
/// for NaN) or "... is not finite: 'inf'".
double parseFinite(std::string_view text, const std::string& prefix, std::string_view name);

/// Throws "<prefix>timestamp goes backwards by X ms" or "<prefix>timestamp repeats the previous one"
/// unless t_ns > previous_t_ns. Every stream here is keyed by time, so equal stamps are ambiguous.
/// Both stamps come from readers that bound them to ±kMaxFileStampNs, so their difference fits in int64_t.
void requireIncreasing(std::int64_t previous_t_ns, std::int64_t t_ns, const std::string& prefix);

/// "33.333 ms": a duration as a person reading an error thinks of it.
std::string formatMs(std::int64_t dt_ns);

}  // namespace vifusion::datasets::detail
