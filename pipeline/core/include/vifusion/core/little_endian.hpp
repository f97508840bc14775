#pragma once
// Little-endian fixed-width integers to and from bytes, assembled byte by byte so that the result is
// the same on any host (compilers turn these into single loads and stores on little-endian CPUs).
// The caller guarantees the bytes exist; the bounds-checked reading is ByteCursor (byte_cursor.hpp).

#include <cstdint>

namespace vifusion {

inline void storeU16(std::uint8_t* out, std::uint16_t value) {
  out[0] = static_cast<std::uint8_t>(value);
  out[1] = static_cast<std::uint8_t>(value >> 8);
}

inline void storeU32(std::uint8_t* out, std::uint32_t value) {
  for (int i = 0; i < 4; ++i) out[i] = static_cast<std::uint8_t>(value >> (8 * i));
}

inline void storeU64(std::uint8_t* out, std::uint64_t value) {
  for (int i = 0; i < 8; ++i) out[i] = static_cast<std::uint8_t>(value >> (8 * i));
}

inline std::uint16_t loadU16(const std::uint8_t* in) {
  return static_cast<std::uint16_t>(in[0] | static_cast<unsigned>(in[1]) << 8);
}

inline std::uint32_t loadU32(const std::uint8_t* in) {
  std::uint32_t value = 0;
  for (int i = 3; i >= 0; --i) value = value << 8 | in[i];
  return value;
}

inline std::uint64_t loadU64(const std::uint8_t* in) {
  std::uint64_t value = 0;
  for (int i = 7; i >= 0; --i) value = value << 8 | in[i];
  return value;
}

}  // namespace vifusion
