#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <span>
#include <string_view>
#include <vector>

#include "vifusion/core/crc32.hpp"

namespace vifusion {
namespace {

std::span<const std::uint8_t> bytes(std::string_view text) {
  return {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()};
}

/// The CRC-32 definition itself, one bit at a time: the oracle for the sliced tables.
std::uint32_t bitwiseCrc32(std::span<const std::uint8_t> data) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (const std::uint8_t byte : data) {
    crc ^= byte;
    for (int bit = 0; bit < 8; ++bit) crc = (crc & 1u) != 0 ? (crc >> 1) ^ 0xEDB88320u : crc >> 1;
  }
  return ~crc;
}

TEST(Crc32, MatchesTheStandardCheckValues) {
  EXPECT_EQ(crc32(bytes("123456789")), 0xCBF43926u);  // the catalogued check value of CRC-32/ISO-HDLC
  EXPECT_EQ(crc32(bytes("The quick brown fox jumps over the lazy dog")), 0x414FA339u);
  EXPECT_EQ(crc32({}), 0u);
}

TEST(Crc32, SlicedEqualsBitwiseForEveryLengthAndAlignment) {
  std::mt19937 random(7);
  std::vector<std::uint8_t> data(300);
  for (std::uint8_t& byte : data) byte = static_cast<std::uint8_t>(random());
  for (std::size_t start = 0; start < 8; ++start) {
    for (std::size_t length = 0; start + length <= 100; ++length) {
      const std::span<const std::uint8_t> piece = std::span(data).subspan(start, length);
      ASSERT_EQ(crc32(piece), bitwiseCrc32(piece)) << "start " << start << ", length " << length;
    }
  }
}

TEST(Crc32, PiecesInOrderEqualTheWhole) {
  const std::span<const std::uint8_t> whole = bytes("a chunk's records, fed to the CRC one message at a time");
  for (std::size_t split = 0; split <= whole.size(); ++split) {
    Crc32 crc;
    crc.update(whole.first(split));
    crc.update(whole.subspan(split));
    ASSERT_EQ(crc.value(), crc32(whole)) << "split at " << split;
  }
  Crc32 crc;
  crc.update(whole);
  crc.reset();
  EXPECT_EQ(crc.value(), 0u);
}

}  // namespace
}  // namespace vifusion
