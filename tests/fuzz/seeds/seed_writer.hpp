#pragma once
// Writes one target's seed files: <root>/<target>/<name>, each the target's selector byte (which parser or
// layout, as the target's first input byte chooses it) followed by the bytes, or the bytes alone.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace vifusion::fuzz::seeds {

class SeedWriter {
 public:
  SeedWriter(const std::filesystem::path& root, const std::string& target);

  void write(const std::string& name, std::optional<std::uint8_t> selector, std::span<const std::uint8_t> bytes);
  void write(const std::string& name, std::optional<std::uint8_t> selector, std::string_view text);

 private:
  std::filesystem::path dir_;
};

/// The first `max_lines` lines of a text file (all of them when it has fewer), newline-terminated.
std::string firstLines(const std::filesystem::path& path, std::size_t max_lines);

/// Joins files with NUL bytes, as the multi-file targets split them.
std::string joinedWithNul(std::initializer_list<std::string_view> files);

// One function per target; `data_dir` is ../shared/data.
void writeCalibrationSeeds(const std::filesystem::path& root);
void writeDatasetListSeeds(const std::filesystem::path& root, const std::filesystem::path& data_dir);
void writeDaemonConfigSeeds(const std::filesystem::path& root, const std::filesystem::path& source_dir);
void writeImageSeeds(const std::filesystem::path& root, const std::filesystem::path& data_dir);
void writeKlgSeeds(const std::filesystem::path& root, const std::filesystem::path& data_dir);
void writeMapFileSeeds(const std::filesystem::path& root);
void writePlySeeds(const std::filesystem::path& root, const std::filesystem::path& data_dir);
void writeCdrSeeds(const std::filesystem::path& root);

}  // namespace vifusion::fuzz::seeds
