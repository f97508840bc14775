#include "vifusion/v4l2/frame_counter_gaps.hpp"

namespace vifusion::v4l2 {
namespace {
// Half the counter range: a forward step larger than this is read as a step backwards.
constexpr std::uint32_t kLargestForwardStep = 1u << 31;
}  // namespace

FrameCounterGaps::Step FrameCounterGaps::observe(std::uint32_t counter) {
  Step step;
  if (have_previous_) {
    step.previous = previous_;
    const std::uint32_t forward = counter - previous_;  // modulo 2³²: wrap-safe
    if (forward == 0 || forward > kLargestForwardStep) {
      step.went_back = true;
      ++regressions_;
    } else {
      step.missing = static_cast<std::int64_t>(forward) - 1;
      missing_frames_ += step.missing;
    }
  }
  have_previous_ = true;
  previous_ = counter;
  return step;
}

}  // namespace vifusion::v4l2
