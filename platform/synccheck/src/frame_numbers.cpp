#include "frame_numbers.hpp"

namespace vifusion::synccheck {

FrameNumberCounts countFrameNumbers(std::span<const CameraFrameTimes> frames, int bits, ProblemLog& problems) {
  FrameNumberCounts counts;
  counts.is_repeat.assign(frames.size(), false);
  for (const CameraFrameTimes& frame : frames) counts.present = counts.present || frame.device_frame_number != 0;
  if (!counts.present) return counts;
  const std::uint64_t modulus = std::uint64_t{1} << bits;
  const std::uint64_t half = modulus / 2;
  for (std::size_t i = 1; i < frames.size(); ++i) {
    const std::uint64_t step =
        (std::uint64_t{frames[i].device_frame_number} + modulus - frames[i - 1].device_frame_number % modulus) %
        modulus;
    if (step == 0) {
      ++counts.repeated;
      counts.is_repeat[i] = true;
    } else if (step >= half) {
      ++counts.backwards;
      problems.note("frame %zu (index %lld): device_frame_number %u is behind the previous %u", i,
                    static_cast<long long>(frames[i].index), frames[i].device_frame_number,
                    frames[i - 1].device_frame_number);
    } else {
      counts.skipped += step - 1;
    }
  }
  return counts;
}

}  // namespace vifusion::synccheck
