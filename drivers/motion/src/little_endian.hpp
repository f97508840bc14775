#pragma once
// Little-endian field access on byte spans (the wire order of every motion-module and adapter field),
// independent of the host's byte order and alignment. Callers check the span is long enough.

#include <cstddef>
#include <cstdint>
#include <span>

namespace vifusion::motion::detail {

inline std::uint16_t readU16(std::span<const std::uint8_t> bytes, std::size_t offset) {
  return static_cast<std::uint16_t>(bytes[offset] | (bytes[offset + 1] << 8));
}

inline std::uint32_t readU32(std::span<const std::uint8_t> bytes, std::size_t offset) {
  return static_cast<std::uint32_t>(bytes[offset]) | (static_cast<std::uint32_t>(bytes[offset + 1]) << 8) |
         (static_cast<std::uint32_t>(bytes[offset + 2]) << 16) | (static_cast<std::uint32_t>(bytes[offset + 3]) << 24);
}

inline std::int16_t readI16(std::span<const std::uint8_t> bytes, std::size_t offset) {
  return static_cast<std::int16_t>(readU16(bytes, offset));  // two's complement (C++20)
}

inline void writeU16(std::span<std::uint8_t> bytes, std::size_t offset, std::uint16_t value) {
  bytes[offset] = static_cast<std::uint8_t>(value & 0xFF);
  bytes[offset + 1] = static_cast<std::uint8_t>(value >> 8);
}

inline void writeU32(std::span<std::uint8_t> bytes, std::size_t offset, std::uint32_t value) {
  for (std::size_t i = 0; i < sizeof(value); ++i) bytes[offset + i] = static_cast<std::uint8_t>(value >> (8 * i));
}

inline void writeI16(std::span<std::uint8_t> bytes, std::size_t offset, std::int16_t value) {
  writeU16(bytes, offset, static_cast<std::uint16_t>(value));
}

}  // namespace vifusion::motion::detail
