#pragma once
// CRC-32 as MCAP uses it (https://mcap.dev/spec: chunk records, attachments, summary) and the map file
// (mapfile/map_file_format.hpp): the IEEE 802.3 polynomial, reflected (0xEDB88320), initial value and
// final XOR 0xFFFFFFFF — zlib's crc32(), so crc32("123456789") == 0xCBF43926.
//
// Our own table CRC rather than zlib's: its users build in the aarch64 cross build, which has no arm64
// zlib (.ci/cross-aarch64). Slicing by 8 bytes keeps it at
// about 1 GB/s on one core, so checking 30 MB/s of images costs a few percent of a core.

#include <cstdint>
#include <span>

namespace vifusion {

/// Running CRC-32 over several pieces: update() in order, value() at any time (it does not finish
/// the running state, so more pieces may follow).
class Crc32 {
 public:
  void update(std::span<const std::uint8_t> bytes);
  std::uint32_t value() const { return ~state_; }
  void reset() { state_ = kInitialState; }

 private:
  static constexpr std::uint32_t kInitialState = 0xFFFFFFFFu;
  std::uint32_t state_ = kInitialState;
};

/// CRC-32 of one piece of bytes.
std::uint32_t crc32(std::span<const std::uint8_t> bytes);

}  // namespace vifusion
