#include "vifusion/v4l2/mid_exposure_clock.hpp"

#include <linux/videodev2.h>

namespace vifusion::v4l2 {
namespace {
const char* clockName(std::uint32_t timestamp_type) {
  switch (timestamp_type) {
    case V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC:
      return "MONOTONIC";
    case V4L2_BUF_FLAG_TIMESTAMP_COPY:
      return "COPY (copied from an output buffer)";
    case V4L2_BUF_FLAG_TIMESTAMP_UNKNOWN:
      return "UNKNOWN";
    default:
      return "not a V4L2 timestamp type";
  }
}
}  // namespace

std::optional<std::int64_t> MidExposureClock::midExposureNs(std::uint32_t buffer_flags, std::int64_t t_stamp_ns,
                                                            const ExposureTiming& timing, ProblemText& problem) {
  const std::uint32_t clock = buffer_flags & V4L2_BUF_FLAG_TIMESTAMP_MASK;
  if (clock != V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC) {
    problem.set("buffer flags 0x%08x: timestamp clock is %s, not CLOCK_MONOTONIC", buffer_flags, clockName(clock));
    return refuse();
  }
  if (t_stamp_ns <= 0) {
    problem.set("buffer timestamp is %lld ns: the driver did not stamp the buffer", static_cast<long long>(t_stamp_ns));
    return refuse();
  }
  if (timing.exposure_ns < 0 || timing.readout_ns < 0) {
    problem.set("exposure %lld ns, readout %lld ns: both must be >= 0", static_cast<long long>(timing.exposure_ns),
                static_cast<long long>(timing.readout_ns));
    return refuse();
  }
  if (have_previous_ && t_stamp_ns <= previous_stamp_ns_) {
    problem.set("buffer timestamp %lld ns is not after the previous one (%lld ns): back by %lld ns",
                static_cast<long long>(t_stamp_ns), static_cast<long long>(previous_stamp_ns_),
                static_cast<long long>(previous_stamp_ns_ - t_stamp_ns));
    return refuse();
  }
  const bool start_of_exposure = (buffer_flags & V4L2_BUF_FLAG_TSTAMP_SRC_MASK) == V4L2_BUF_FLAG_TSTAMP_SRC_SOE;
  const std::int64_t half_exposure_ns = timing.exposure_ns / 2;
  const std::int64_t t_mid_ns =
      start_of_exposure ? t_stamp_ns + half_exposure_ns : t_stamp_ns - timing.readout_ns - half_exposure_ns;
  if (have_previous_ && t_mid_ns <= previous_mid_ns_) {
    problem.set("mid-exposure time is not after the previous frame's: back by %lld ns (exposure %lld ns)",
                static_cast<long long>(previous_mid_ns_ - t_mid_ns), static_cast<long long>(timing.exposure_ns));
    return refuse();
  }
  have_previous_ = true;
  previous_stamp_ns_ = t_stamp_ns;
  previous_mid_ns_ = t_mid_ns;
  return t_mid_ns;
}

}  // namespace vifusion::v4l2
