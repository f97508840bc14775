#pragma once
// Parser of the motion module's interrupt transfers (layout: packet_format.hpp) into raw entries.
//
// What is dropped, and why (each counted per PacketDropReason and described by describe(PacketProblem)):
//  - a transfer shorter than one packet; bytes after the last whole packet;
//  - a packet whose error_bitmask is non-zero, and every later packet of the same transfer: the device
//    declares its data bad (FIFO overflow, CRC, IMU not responding), and a burst after such a report cannot
//    be trusted either (librealsense v1.12.4 stops at that packet too);
//  - a packet whose imu_entry_count or timestamp_entry_count is above its slot count (a corrupt header);
//  - an entry with a source code that does not belong in its slot kind, or an IMU entry with the valid
//    bit clear;
//  - an entry whose 12-bit counter repeats or steps back relative to the previous entry of its source.
//
// Where the counter check lives: here, because the parser is the one place that sees every entry in the
// device's order before anything downstream has dropped or reordered it, and because the check needs only
// the last 12-bit counter per source (7 × u16), not unwrapped time. A step of 1…2047 (mod 4096) is progress
// (gaps are losses upstream, reported by the clock module's unwrapper); 0 is a repeat; 2048…4095 is a step
// back. After a step back the source re-anchors on the new counter, so a device that restarted its counters
// loses one entry, not 8 s of data until the old count is passed again. The ticks are not checked here:
// they go to the clock mapper, which rejects device time that goes backwards with its own counted reason.
//
// Threading: one parser per device, used by the USB thread only. No allocation after construction.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "vifusion/motion/packet_format.hpp"
#include "vifusion/motion/packet_problem.hpp"
#include "vifusion/motion/parsed_transfer.hpp"

namespace vifusion::motion {

/// Running totals since construction or reset().
struct PacketParserStats {
  std::uint64_t transfers = 0;
  std::uint64_t empty_transfers = 0;  ///< zero-byte transfers: a quiet endpoint, not a problem
  std::uint64_t packets = 0;          ///< whole packets seen
  std::uint64_t packets_accepted = 0;
  std::uint64_t imu_entries = 0;        ///< accepted IMU entries
  std::uint64_t timestamp_entries = 0;  ///< accepted timestamp entries
  /// Accepted packets whose CX3 counter is not the previous accepted packet's + 1 (mod 16). Whether the
  /// bridge counts packets or transfers is unconfirmed, so this is reported, never a reason to drop.
  std::uint64_t cx3_counter_skips = 0;
  /// Per reason: transfers (kShortTransfer, kPartialPacket), packets or entries dropped.
  std::array<std::uint64_t, kPacketDropReasonCount> drop_counts{};
  /// Per ErrorFlag: packets that reported it.
  std::array<std::uint64_t, kErrorFlagCount> error_flag_counts{};

  std::uint64_t dropCount(PacketDropReason reason) const { return drop_counts[static_cast<std::size_t>(reason)]; }
  std::uint64_t errorFlagCount(ErrorFlag flag) const { return error_flag_counts[static_cast<std::size_t>(flag)]; }
  std::uint64_t totalDrops() const;
};

class PacketParser {
 public:
  /// Decodes one interrupt transfer into `out` (cleared first). Never throws on any byte content.
  /// @return the number of problems met (also in out.problemCount()); 0 when everything was accepted.
  std::size_t parse(std::span<const std::uint8_t> transfer, ParsedTransfer& out);

  const PacketParserStats& stats() const { return stats_; }
  /// The most recent problem; meaningful once stats().totalDrops() > 0.
  const PacketProblem& lastProblem() const { return last_problem_; }

  /// Forgets the counters and statistics, e.g. after the device was re-opened.
  void reset();

 private:
  void parsePacket(std::span<const std::uint8_t> packet, std::uint32_t packet_index, ParsedTransfer& out);
  /// Counter check for one entry of `source`; true if the entry may be kept.
  bool acceptCounter(EventSource source, std::uint16_t counter, std::uint32_t packet_index, std::uint32_t slot,
                     ParsedTransfer& out);
  void report(const PacketProblem& problem, ParsedTransfer& out);
  void trackCx3Counter(std::uint8_t counter);

  PacketParserStats stats_;
  PacketProblem last_problem_;
  std::array<std::uint16_t, kSourceCodeCount> last_counter_{};  ///< per source code
  std::array<bool, kSourceCodeCount> has_counter_{};
  std::uint8_t last_cx3_counter_ = 0;
  bool has_cx3_counter_ = false;
};

}  // namespace vifusion::motion
