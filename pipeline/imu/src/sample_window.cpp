#include "vifusion/imu/sample_window.hpp"

#include <algorithm>
#include <cinttypes>
#include <cstdio>

#include "vifusion/core/time.hpp"

namespace vifusion::imu {
namespace {

double nsToMs(std::int64_t dt_ns) { return static_cast<double>(dt_ns) / static_cast<double>(kNsPerMillisecond); }

bool finite(const ImuSample& s) { return s.gyro_rad_s.allFinite() && s.accel_mps2.allFinite(); }

}  // namespace

std::string ImuSampleIssue::message() const {
  char text[256] = {};
  switch (problem) {
    case ImuSampleProblem::kEmptyInterval:
      std::snprintf(text, sizeof text, "frame interval ends at t_ns=%" PRId64 ", not after its start t_ns=%" PRId64,
                    t_ns, other_t_ns);
      break;
    case ImuSampleProblem::kNoSamples:
      std::snprintf(text, sizeof text, "no IMU samples for the frame interval t_ns=%" PRId64 " to %" PRId64, t_ns,
                    other_t_ns);
      break;
    case ImuSampleProblem::kOutOfOrder:
      std::snprintf(text, sizeof text,
                    "IMU sample at t_ns=%" PRId64
                    ": timestamp goes backwards by %.3f ms (previous sample at t_ns=%" PRId64 ")",
                    t_ns, nsToMs(other_t_ns - t_ns), other_t_ns);
      break;
    case ImuSampleProblem::kDuplicate:
      std::snprintf(text, sizeof text,
                    "IMU sample at t_ns=%" PRId64 ": duplicate timestamp (the previous sample has it too)", t_ns);
      break;
    case ImuSampleProblem::kNotCovered:
      std::snprintf(text, sizeof text,
                    "frame time t_ns=%" PRId64 ": no IMU sample at or %s it (%s sample at t_ns=%" PRId64 ")", t_ns,
                    other_t_ns > t_ns ? "before" : "after", other_t_ns > t_ns ? "first" : "last", other_t_ns);
      break;
    case ImuSampleProblem::kGap:
      std::snprintf(text, sizeof text,
                    "IMU sample at t_ns=%" PRId64 ": gap of %.3f ms since the previous sample at t_ns=%" PRId64
                    " (at most %.3f ms allowed)",
                    t_ns, nsToMs(t_ns - other_t_ns), other_t_ns, nsToMs(limit_ns));
      break;
    case ImuSampleProblem::kNonFinite:
      std::snprintf(text, sizeof text, "IMU sample at t_ns=%" PRId64 ": reading is not finite", t_ns);
      break;
  }
  return text;
}

std::optional<ImuSampleIssue> checkSampleWindow(std::span<const ImuSample> samples, std::int64_t t0_ns,
                                                std::int64_t t1_ns, std::int64_t max_gap_ns, SampleRange& range) {
  if (t1_ns <= t0_ns) return ImuSampleIssue{ImuSampleProblem::kEmptyInterval, t1_ns, t0_ns};
  if (samples.empty()) return ImuSampleIssue{ImuSampleProblem::kNoSamples, t0_ns, t1_ns};
  for (std::size_t k = 1; k < samples.size(); ++k) {
    const std::int64_t previous_ns = samples[k - 1].t_ns;
    const std::int64_t t_ns = samples[k].t_ns;
    if (t_ns == previous_ns) return ImuSampleIssue{ImuSampleProblem::kDuplicate, t_ns, previous_ns};
    if (t_ns < previous_ns) return ImuSampleIssue{ImuSampleProblem::kOutOfOrder, t_ns, previous_ns};
  }
  if (samples.front().t_ns > t0_ns) return ImuSampleIssue{ImuSampleProblem::kNotCovered, t0_ns, samples.front().t_ns};
  if (samples.back().t_ns < t1_ns) return ImuSampleIssue{ImuSampleProblem::kNotCovered, t1_ns, samples.back().t_ns};

  // Stamps increase strictly now, so binary search finds the bracketing samples.
  const auto after_t0 = std::upper_bound(samples.begin(), samples.end(), t0_ns,
                                         [](std::int64_t t_ns, const ImuSample& s) { return t_ns < s.t_ns; });
  const auto at_or_after_t1 = std::lower_bound(samples.begin(), samples.end(), t1_ns,
                                               [](const ImuSample& s, std::int64_t t_ns) { return s.t_ns < t_ns; });
  const auto first = static_cast<std::size_t>(after_t0 - samples.begin()) - 1;
  const auto last = static_cast<std::size_t>(at_or_after_t1 - samples.begin());
  for (std::size_t k = first; k <= last; ++k) {
    if (!finite(samples[k])) return ImuSampleIssue{ImuSampleProblem::kNonFinite, samples[k].t_ns};
    if (k > first && samples[k].t_ns - samples[k - 1].t_ns > max_gap_ns) {
      return ImuSampleIssue{ImuSampleProblem::kGap, samples[k].t_ns, samples[k - 1].t_ns, max_gap_ns};
    }
  }
  range = {first, last};
  return std::nullopt;
}

}  // namespace vifusion::imu

namespace vifusion::imu {

std::span<const ImuSample> bracketingSamples(std::span<const ImuSample> stream, std::int64_t t0_ns,
                                             std::int64_t t1_ns) {
  if (stream.empty()) return stream;
  const auto after_t0 = std::upper_bound(stream.begin(), stream.end(), t0_ns,
                                         [](std::int64_t t_ns, const ImuSample& s) { return t_ns < s.t_ns; });
  const auto at_or_after_t1 = std::lower_bound(stream.begin(), stream.end(), t1_ns,
                                               [](const ImuSample& s, std::int64_t t_ns) { return s.t_ns < t_ns; });
  const auto first = after_t0 == stream.begin() ? stream.begin() : after_t0 - 1;
  const auto last = at_or_after_t1 == stream.end() ? stream.end() : at_or_after_t1 + 1;
  if (first >= last) return stream.subspan(static_cast<std::size_t>(first - stream.begin()), 1);
  return std::span<const ImuSample>(first, last);
}

}  // namespace vifusion::imu
