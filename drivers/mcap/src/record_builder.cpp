#include "record_builder.hpp"

#include <cstring>

#include "vifusion/core/little_endian.hpp"

namespace vifusion::mcap::detail {

std::size_t RecordBuilder::beginRecord(Opcode opcode) {
  const std::size_t start = bytes_.size();
  u8(static_cast<std::uint8_t>(opcode));
  u64(0);
  return start;
}

void RecordBuilder::endRecord(std::size_t start) {
  storeU64(bytes_.data() + start + kRecordLengthAt, bytes_.size() - start - kRecordHeaderBytes);
}

std::size_t RecordBuilder::beginLengthPrefix() {
  const std::size_t position = bytes_.size();
  u32(0);
  return position;
}

void RecordBuilder::endLengthPrefix(std::size_t position) {
  storeU32(bytes_.data() + position, static_cast<std::uint32_t>(bytes_.size() - position - 4));
}

void RecordBuilder::raw(std::span<const std::uint8_t> bytes) {
  // resize + memcpy rather than insert(): GCC 12 misreports insert() after clear() under
  // -Wstringop-overflow (a known false positive), and this is as fast.
  if (bytes.empty()) return;
  const std::size_t at = bytes_.size();
  bytes_.resize(at + bytes.size());
  std::memcpy(bytes_.data() + at, bytes.data(), bytes.size());
}

void RecordBuilder::u16(std::uint16_t value) {
  std::uint8_t field[2];
  storeU16(field, value);
  raw(field);
}

void RecordBuilder::u32(std::uint32_t value) {
  std::uint8_t field[4];
  storeU32(field, value);
  raw(field);
}

void RecordBuilder::u64(std::uint64_t value) {
  std::uint8_t field[8];
  storeU64(field, value);
  raw(field);
}

void RecordBuilder::string(std::string_view text) {
  u32(static_cast<std::uint32_t>(text.size()));
  raw({reinterpret_cast<const std::uint8_t*>(text.data()), text.size()});
}

void RecordBuilder::stringMap(const std::map<std::string, std::string>& map) {
  const std::size_t length = beginLengthPrefix();
  for (const auto& [key, value] : map) {
    string(key);
    string(value);
  }
  endLengthPrefix(length);
}

}  // namespace vifusion::mcap::detail
