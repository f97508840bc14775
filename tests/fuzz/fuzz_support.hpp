#pragma once
// What the parser targets share: a trap for a broken promise, the input as files for parsers that take a
// path, and the rule every parser of outside input keeps: it succeeds, or it throws vifusion::Error whose
// message names the input. Any other exception escapes LLVMFuzzerTestOneInput, which libFuzzer reports as a
// crash with the input that caused it.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "vifusion/core/error.hpp"

namespace vifusion::fuzz {

inline void require(bool condition) {
  if (!condition) __builtin_trap();
}

/// Runs `parse`; a vifusion::Error must name one of `names` (a file or type name), else the run traps.
/// Returns whether `parse` succeeded.
template <typename Parse>
bool parsedOrNamedError(std::initializer_list<std::string_view> names, Parse&& parse) {
  try {
    parse();
    return true;
  } catch (const Error& error) {
    const std::string_view message = error.what();
    bool named = false;
    for (const std::string_view name : names) named = named || message.find(name) != std::string_view::npos;
    require(named);
    return false;
  }
}

/// A private folder under $TMPDIR (or /tmp) for this process, removed at exit; parsers that take paths read
/// the input from files written here. One per process keeps parallel fuzzing jobs (-jobs=N) apart.
class ScratchFolder {
 public:
  ScratchFolder() {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern = std::string(tmp != nullptr && *tmp != '\0' ? tmp : "/tmp") + "/vifusion-fuzz-XXXXXX";
    require(::mkdtemp(pattern.data()) != nullptr);
    path_ = pattern;
  }
  ~ScratchFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;

  const std::filesystem::path& path() const { return path_; }

  /// Writes `bytes` to `name` inside the folder, replacing what was there.
  std::filesystem::path write(const std::string& name, std::span<const std::uint8_t> bytes) const {
    const std::filesystem::path file = path_ / name;
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    require(static_cast<bool>(out));
    return file;
  }

  /// Removes every file in the folder (not the folder), so each input starts from nothing.
  void clear() const {
    for (const auto& entry : std::filesystem::directory_iterator(path_)) std::filesystem::remove_all(entry.path());
  }

 private:
  std::filesystem::path path_;
};

/// Splits `bytes` at NUL bytes into at most `max_parts` parts (the last keeps any further NULs). Text formats
/// hold no NUL, so a multi-file input is its files joined by NULs, and the fuzzer can cut and move them.
inline std::vector<std::span<const std::uint8_t>> splitAtNul(std::span<const std::uint8_t> bytes,
                                                             std::size_t max_parts) {
  std::vector<std::span<const std::uint8_t>> parts;
  std::size_t start = 0;
  for (std::size_t i = 0; i < bytes.size() && parts.size() + 1 < max_parts; ++i) {
    if (bytes[i] != 0) continue;
    parts.push_back(bytes.subspan(start, i - start));
    start = i + 1;
  }
  parts.push_back(bytes.subspan(start));
  return parts;
}

inline std::string_view asText(std::span<const std::uint8_t> bytes) {
  return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

}  // namespace vifusion::fuzz
