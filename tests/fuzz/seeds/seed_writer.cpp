#include "seed_writer.hpp"

#include <fstream>

#include "vifusion/core/error.hpp"

namespace vifusion::fuzz::seeds {

SeedWriter::SeedWriter(const std::filesystem::path& root, const std::string& target) : dir_(root / target) {
  std::filesystem::remove_all(dir_);
  std::filesystem::create_directories(dir_);
}

void SeedWriter::write(const std::string& name, std::optional<std::uint8_t> selector,
                       std::span<const std::uint8_t> bytes) {
  std::ofstream out(dir_ / name, std::ios::binary);
  if (selector) out.put(static_cast<char>(*selector));
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw Error((dir_ / name).string() + ": cannot write the seed");
}

void SeedWriter::write(const std::string& name, std::optional<std::uint8_t> selector, std::string_view text) {
  write(name, selector, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

std::string firstLines(const std::filesystem::path& path, std::size_t max_lines) {
  std::ifstream in(path);
  if (!in) throw Error(path.string() + ": cannot read the test data a seed is cut from");
  std::string text, line;
  for (std::size_t n = 0; n < max_lines && std::getline(in, line); ++n) text += line + "\n";
  return text;
}

std::string joinedWithNul(std::initializer_list<std::string_view> files) {
  std::string joined;
  for (const std::string_view file : files) {
    if (!joined.empty()) joined.push_back('\0');
    joined += file;
  }
  return joined;
}

}  // namespace vifusion::fuzz::seeds
