#pragma once
// The inverse of the parser: MotionPacket fields → the documented bytes (packet_format.hpp). Tests and the
// scripted device of the integration tests build their byte fixtures with it, so fixtures follow the
// documented layout rather than bytes captured from somewhere. It writes what it is given, including
// counts above the slot counts, invalid source codes, error bits and clear valid bits, so that corrupt
// packets can be made on purpose; fields too wide for their bits are refused instead of being cut.

#include <cstddef>
#include <cstdint>
#include <span>

#include "vifusion/motion/motion_packet.hpp"
#include "vifusion/motion/packet_format.hpp"

namespace vifusion::motion {

/// Writes one packet into exactly kPacketBytes bytes.
/// @throws vifusion::Error naming the field if a counter exceeds 12 bits, the CX3 counter 4 bits or a source
///         code 3 bits.
void encodePacket(const MotionPacket& packet, std::span<std::uint8_t, kPacketBytes> out);

/// Writes packets back to back, as one interrupt transfer; returns the bytes written.
/// @throws vifusion::Error if `out` is too small, or as encodePacket().
std::size_t encodeTransfer(std::span<const MotionPacket> packets, std::span<std::uint8_t> out);

}  // namespace vifusion::motion
