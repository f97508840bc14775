#pragma once
// Serialises MCAP records into a byte vector: fixed-width little-endian fields, length-prefixed strings,
// byte fields, arrays and maps, and record framing whose content length is patched in at the end.
// Within its reserved capacity it never allocates, which is how the writer builds Message Index records
// per chunk; registration, attachments and the summary may grow it.

#include <cstddef>
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "vifusion/mcap/mcap_format.hpp"

namespace vifusion::mcap::detail {

class RecordBuilder {
 public:
  void reserve(std::size_t bytes) { bytes_.reserve(bytes); }
  void clear() { bytes_.clear(); }
  std::size_t size() const { return bytes_.size(); }
  std::size_t capacity() const { return bytes_.capacity(); }
  std::span<const std::uint8_t> bytes() const { return bytes_; }
  /// For filling in fields laid out earlier (placeholders); valid until the builder grows.
  std::uint8_t* data() { return bytes_.data(); }

  /// Writes the opcode and a placeholder length; returns the record's start for endRecord().
  std::size_t beginRecord(Opcode opcode);
  /// Patches the content length of the record begun at `start`.
  void endRecord(std::size_t start);
  /// A u32 byte-length placeholder (Array, Map); returns its position for endLengthPrefix().
  std::size_t beginLengthPrefix();
  void endLengthPrefix(std::size_t position);

  void u8(std::uint8_t value) { bytes_.push_back(value); }
  void u16(std::uint16_t value);
  void u32(std::uint32_t value);
  void u64(std::uint64_t value);
  /// A timestamp: int64 ns, non-negative (callers check), stored as u64.
  void time(std::int64_t t_ns) { u64(static_cast<std::uint64_t>(t_ns)); }
  void raw(std::span<const std::uint8_t> bytes);
  /// String: u32 length + bytes.
  void string(std::string_view text);
  /// Map<string, string>: u32 byte length + key/value strings.
  void stringMap(const std::map<std::string, std::string>& map);

 private:
  std::vector<std::uint8_t> bytes_;
};

}  // namespace vifusion::mcap::detail
