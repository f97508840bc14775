#pragma once
// The device's frame counter across delivered frames: numbers skipped (drops the device saw happen),
// repeated (a frame delivered twice) and going back (a counter restart or a corrupt row).

#include <cstdint>
#include <span>
#include <vector>

#include "problem_log.hpp"
#include "vifusion/synccheck/sync_input.hpp"

namespace vifusion::synccheck {

struct FrameNumberCounts {
  bool present = false;         ///< some frame carries a non-zero number
  std::uint64_t skipped = 0;    ///< numbers missing between consecutive frames
  std::size_t repeated = 0;     ///< frames with the previous frame's number
  std::size_t backwards = 0;    ///< frames whose number is behind the previous one
  std::vector<bool> is_repeat;  ///< per frame: it repeats the previous number
};

/// Differences are taken modulo 2^bits (bits in [1, 32]); one that is half the modulus or more is a step
/// back, not a gap (a 32-bit counter cannot skip 2^31 frames; a 12-bit one not 2048, 68 s at 30 Hz).
/// Steps back are noted in `problems`.
FrameNumberCounts countFrameNumbers(std::span<const CameraFrameTimes> frames, int bits, ProblemLog& problems);

}  // namespace vifusion::synccheck
