#include "vifusion/map/surfel_ply.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <string>
#include <vector>

#include "vifusion/core/atomic_file.hpp"
#include "vifusion/core/error.hpp"

namespace vifusion::map {
namespace {

constexpr std::size_t kVertexBytes = 35;         ///< 8 floats and 3 uchars, packed
constexpr std::size_t kVerticesPerWrite = 4096;  ///< 140 KiB per write() call

bool exported(const Surfel& surfel, const SurfelPlyOptions& options) {
  return !(surfel.position_confidence.w() < options.min_confidence);
}

/// Shortest decimal text that reads back as `value`.
std::string shortest(float value) {
  std::array<char, 32> text{};
  const auto result = std::to_chars(text.data(), text.data() + text.size(), value);
  return std::string(text.data(), result.ptr);
}

std::string header(std::size_t vertices, const SurfelPlyOptions& options) {
  std::string text =
      "ply\n"
      "format binary_little_endian 1.0\n"
      "comment vifusion surfel map: x y z [m], nx ny nz in the map world frame W, radius [m]\n";
  text += "comment min_confidence " + shortest(options.min_confidence) + "\n";
  text += "element vertex " + std::to_string(vertices) + "\n";
  return text +
         "property float x\n"
         "property float y\n"
         "property float z\n"
         "property float nx\n"
         "property float ny\n"
         "property float nz\n"
         "property uchar red\n"
         "property uchar green\n"
         "property uchar blue\n"
         "property float radius\n"
         "property float confidence\n"
         "end_header\n";
}

/// Little-endian whatever the host.
std::byte* putFloat(std::byte* out, float value) {
  const auto bits = std::bit_cast<std::uint32_t>(value);
  for (int i = 0; i < 4; ++i) *out++ = static_cast<std::byte>((bits >> (8 * i)) & 0xffu);
  return out;
}

void putVertex(std::byte* out, const Surfel& s) {
  for (int i = 0; i < 3; ++i) out = putFloat(out, s.position_confidence[i]);
  for (int i = 0; i < 3; ++i) out = putFloat(out, s.normal_radius[i]);
  const std::uint32_t rgb = s.packedColour();
  for (int i = 0; i < 3; ++i) *out++ = static_cast<std::byte>((rgb >> (8 * i)) & 0xffu);
  out = putFloat(out, s.normal_radius.w());
  putFloat(out, s.position_confidence.w());
}

}  // namespace

void SurfelPlyOptions::validate() const {
  if (!(std::isfinite(min_confidence) && min_confidence >= 0.0f)) {
    throw Error("surfel PLY option 'min_confidence' must be finite and ≥ 0");
  }
}

SurfelPlyOptions SurfelPlyOptions::stableOnly(const MapOptions& map) {
  SurfelPlyOptions options;
  options.min_confidence = map.confidence_threshold;
  return options;
}

std::size_t writeSurfelPly(const std::filesystem::path& path, std::span<const Surfel> surfels,
                           const SurfelPlyOptions& options) {
  options.validate();
  const auto vertices = static_cast<std::size_t>(
      std::count_if(surfels.begin(), surfels.end(), [&](const Surfel& s) { return exported(s, options); }));
  AtomicFile file(path);
  const std::string text = header(vertices, options);
  file.write(std::as_bytes(std::span(text)));
  std::vector<std::byte> block(kVerticesPerWrite * kVertexBytes);
  std::size_t filled = 0;
  for (const Surfel& s : surfels) {
    if (!exported(s, options)) continue;
    putVertex(block.data() + filled * kVertexBytes, s);
    if (++filled == kVerticesPerWrite) {
      file.write(block);
      filled = 0;
    }
  }
  file.write(std::span(block).first(filled * kVertexBytes));
  file.commit();
  return vertices;
}

}  // namespace vifusion::map
