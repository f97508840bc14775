#pragma once
// The map file's container, format version 1. Every integer and float is little-endian and fixed width
// (IEEE-754 binary32 / binary64), so a map written on amd64 reads bit for bit on arm64.
//
//   file header (16 bytes): magic "VIFUSMAP" | u32 format version | u32 CRC-32 of the 12 bytes before it
//   then the sections, in the order of MapSection, each:
//     section header (24 bytes): tag (8 ASCII bytes, NUL-padded) | u64 payload bytes |
//                                u32 CRC-32 of the payload | u32 CRC-32 of the 20 header bytes before it
//     payload (map_sections.hpp says what each holds)
//   the last section is `end`, with an empty payload: a file without it was cut.
//
// CRC-32 is core/crc32.hpp's (zlib's). A reader refuses a file whose version is newer than its own with a
// message saying so; an older version would be read by a converter kept for it (none yet: this is the first).

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

namespace vifusion::mapfile {

inline constexpr std::array<char, 8> kMagic = {'V', 'I', 'F', 'U', 'S', 'M', 'A', 'P'};
/// The version this build writes and the newest it reads.
inline constexpr std::uint32_t kFormatVersion = 1;
inline constexpr std::size_t kFileHeaderBytes = 16;
inline constexpr std::size_t kSectionTagBytes = 8;
inline constexpr std::size_t kSectionHeaderBytes = 24;

/// The sections, in file order.
enum class MapSection : std::uint8_t {
  kMeta,         ///< what the map is: mode, frames, times, counts
  kCalibration,  ///< the rig it was built with
  kState,        ///< the estimator's last state: gravity direction in W, biases, velocity
  kTrajectory,   ///< every frame's pose in W, moved by every closure of the run
  kKeyframes,    ///< the fern database: options (its seed draws the ferns again) and keyframes
  kSurfels,      ///< every surfel, active and inactive, in map order
  kEnd,          ///< empty: the file is complete
};
inline constexpr int kSectionCount = static_cast<int>(MapSection::kEnd) + 1;

/// The section's tag in the file and in messages ("surfels").
std::string_view sectionName(MapSection section);
/// The section with this tag (the 8 bytes as stored), if any.
std::optional<MapSection> sectionFromTag(const std::array<char, kSectionTagBytes>& tag);

}  // namespace vifusion::mapfile
