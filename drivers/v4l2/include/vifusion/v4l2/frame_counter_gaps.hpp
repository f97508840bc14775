#pragma once
// Dropped-frame accounting from a 32-bit counter that goes up by one per frame: the V4L2 buffer sequence
// (frames the kernel saw, including those it had no buffer for) or a counter embedded in the image by the
// camera (frames the camera made, including those lost on USB). Steps are taken modulo 2³², so the counter
// may wrap; a step of 0 or of more than 2³¹ is "went back" (a repeat or a device reset), not 4 billion
// lost frames, and the counting restarts from the new value.

#include <cstdint>

namespace vifusion::v4l2 {

class FrameCounterGaps {
 public:
  struct Step {
    std::int64_t missing = 0;    ///< frames skipped between the previous counter and this one
    bool went_back = false;      ///< this counter is not after the previous one
    std::uint32_t previous = 0;  ///< the previous counter (meaningful when missing > 0 or went_back)
  };

  /// Takes the next counter. The first one after construction or reset() only sets the base.
  Step observe(std::uint32_t counter);
  void reset() { have_previous_ = false; }

  std::int64_t missingFrames() const { return missing_frames_; }
  std::int64_t regressions() const { return regressions_; }

 private:
  bool have_previous_ = false;
  std::uint32_t previous_ = 0;
  std::int64_t missing_frames_ = 0;
  std::int64_t regressions_ = 0;
};

}  // namespace vifusion::v4l2
