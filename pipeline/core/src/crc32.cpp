#include "vifusion/core/crc32.hpp"

#include <array>
#include <cstddef>

namespace vifusion {
namespace {

constexpr std::uint32_t kReflectedPolynomial = 0xEDB88320u;  // IEEE 802.3, bit-reversed
constexpr std::size_t kTableCount = 8;                       // bytes consumed per step of the fast loop
constexpr std::size_t kTableSize = 256;                      // one entry per byte value

using CrcTables = std::array<std::array<std::uint32_t, kTableSize>, kTableCount>;

/// tables[0] is the classic byte-at-a-time table; tables[k][b] is the CRC of byte b followed by k zero
/// bytes, which lets one step fold 8 input bytes with 8 independent lookups ("slicing by 8").
constexpr CrcTables makeTables() {
  CrcTables tables{};
  for (std::uint32_t b = 0; b < kTableSize; ++b) {
    std::uint32_t crc = b;
    for (int bit = 0; bit < 8; ++bit) crc = (crc & 1u) != 0 ? (crc >> 1) ^ kReflectedPolynomial : crc >> 1;
    tables[0][b] = crc;
  }
  for (std::size_t k = 1; k < kTableCount; ++k) {
    for (std::uint32_t b = 0; b < kTableSize; ++b) {
      const std::uint32_t previous = tables[k - 1][b];
      tables[k][b] = (previous >> 8) ^ tables[0][previous & 0xFFu];
    }
  }
  return tables;
}

constexpr CrcTables kTables = makeTables();

}  // namespace

void Crc32::update(std::span<const std::uint8_t> bytes) {
  std::uint32_t crc = state_;
  const std::uint8_t* p = bytes.data();
  std::size_t n = bytes.size();
  // Little-endian assembly from bytes, so the result is the same on any host byte order.
  while (n >= kTableCount) {
    const std::uint32_t low = crc ^ (static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 |
                                     static_cast<std::uint32_t>(p[2]) << 16 | static_cast<std::uint32_t>(p[3]) << 24);
    crc = kTables[7][low & 0xFFu] ^ kTables[6][(low >> 8) & 0xFFu] ^ kTables[5][(low >> 16) & 0xFFu] ^
          kTables[4][low >> 24] ^ kTables[3][p[4]] ^ kTables[2][p[5]] ^ kTables[1][p[6]] ^ kTables[0][p[7]];
    p += kTableCount;
    n -= kTableCount;
  }
  while (n-- > 0) crc = (crc >> 8) ^ kTables[0][(crc ^ *p++) & 0xFFu];
  state_ = crc;
}

std::uint32_t crc32(std::span<const std::uint8_t> bytes) {
  Crc32 crc;
  crc.update(bytes);
  return crc.value();
}

}  // namespace vifusion
