#pragma once
// The byte format of ROS 2 messages in bags and on the wire: plain CDR (OMG CDR as DDS-XTypes calls
// XCDR1), which ROS 2's rmw layers use for every message type. A message is a 4-byte encapsulation
// header, then the fields in order, each primitive aligned to its own size (1, 2, 4, 8 bytes) counted
// from the END of that header, padding bytes zero. string: uint32 length including the NUL, the bytes,
// the NUL. sequence<T> (T[]): uint32 element count, then the elements. T[N]: the N elements only.
// Nested messages add no bytes of their own. In MCAP: Channel.message_encoding "cdr", Schema.encoding
// "ros2msg" with the definition texts of definitions.hpp.

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace vifusion::ros2_msgs {

// Primitives are copied to and from the buffer with memcpy in host byte order. Every target vifusion
// builds for (x86-64, aarch64) is little-endian, and so is what we write (CDR_LE, the encapsulation
// rmw uses on such hosts); a big-endian host would need a byte swap on every field, which no target
// needs, so it fails to compile instead of writing or reading wrong numbers.
static_assert(std::endian::native == std::endian::little,
              "vifusion::ros2_msgs copies CDR_LE primitives in host order: little-endian hosts only");

/// Bytes before the first field: the representation identifier (2 bytes, big-endian) and 2 option bytes.
inline constexpr std::size_t kEncapsulationHeaderBytes = 4;
/// Representation identifier 0x0001 (CDR_LE: plain CDR, little-endian), options 0x0000.
inline constexpr std::array<std::uint8_t, kEncapsulationHeaderBytes> kCdrLittleEndianHeader{0x00, 0x01, 0x00, 0x00};
/// The largest alignment plain CDR asks for [bytes]: 8-byte primitives (XCDR2 would cap it at 4).
inline constexpr std::size_t kMaxPrimitiveAlignment = 8;

/// MCAP Channel.message_encoding of a ROS 2 CDR message (as rosbag2's MCAP storage writes it).
inline constexpr std::string_view kMcapMessageEncoding = "cdr";
/// MCAP Schema.encoding of the definition texts (definitions.hpp).
inline constexpr std::string_view kMcapSchemaEncoding = "ros2msg";

}  // namespace vifusion::ros2_msgs
