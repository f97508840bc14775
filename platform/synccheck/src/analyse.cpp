#include "vifusion/synccheck/analyse.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "clock_residual_stats.hpp"
#include "edge_pairing.hpp"
#include "frame_numbers.hpp"
#include "imu_stats.hpp"
#include "problem_log.hpp"
#include "sample_stats.hpp"
#include "stream_stats.hpp"
#include "sync_checks.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion::synccheck {
namespace {

/// The edges of the chosen polarity in increasing time; counts lost and out-of-order ones.
std::vector<std::int64_t> usableEdges(const std::vector<SyncEdgeTime>& edges, EdgePolarity polarity, EdgeStats& stats,
                                      ProblemLog& problems) {
  const bool want_rising = polarity == EdgePolarity::kRising;
  std::vector<std::int64_t> times;
  times.reserve(edges.size());
  stats.polarity = polarity;
  stats.count = edges.size();
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const SyncEdgeTime& edge = edges[i];
    if (i > 0 && edge.sequence > edges[i - 1].sequence + 1) {
      stats.lost_by_driver += edge.sequence - edges[i - 1].sequence - 1;
    } else if (i > 0 && edge.sequence <= edges[i - 1].sequence) {
      problems.note("edge %zu: sequence %llu does not follow %llu", i, static_cast<unsigned long long>(edge.sequence),
                    static_cast<unsigned long long>(edges[i - 1].sequence));
    }
    if (edge.rising != want_rising) continue;
    if (!times.empty() && edge.t_ns <= times.back()) {
      ++stats.out_of_order;
      problems.note("edge %zu (sequence %llu): t_ns goes backwards by %lld ns, edge not used", i,
                    static_cast<unsigned long long>(edge.sequence), static_cast<long long>(times.back() - edge.t_ns));
      continue;
    }
    times.push_back(edge.t_ns);
  }
  stats.used = times.size();
  std::vector<double> intervals_ns;
  for (std::size_t i = 1; i < times.size(); ++i) intervals_ns.push_back(static_cast<double>(times[i] - times[i - 1]));
  stats.period_ns = median(std::move(intervals_ns));
  return times;
}

/// Counts how frames were stamped, their order and rate.
void countFrames(const std::vector<CameraFrameTimes>& frames, FrameStats& stats, ProblemLog& problems) {
  stats.count = frames.size();
  std::vector<double> intervals_ns;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const CameraFrameTimes& frame = frames[i];
    if (frame.device_event_ns != 0) ++stats.with_device_event;
    if (frame.stamped_by_device_event) {
      ++stats.stamped_by_device_event;
    } else {
      ++stats.stamped_by_kernel;
    }
    if (i == 0) continue;
    const std::int64_t dt_ns = frame.t_ns - frames[i - 1].t_ns;
    if (dt_ns > 0) intervals_ns.push_back(static_cast<double>(dt_ns));
    if (dt_ns < 0) {  // a repeated stamp (dt 0) is a duplicate, counted with the pairs
      ++stats.out_of_order;
      problems.note("frame %zu (index %lld): t_ns goes backwards by %lld ns", i, static_cast<long long>(frame.index),
                    static_cast<long long>(-dt_ns));
    }
  }
  const double median_interval_ns = median(std::move(intervals_ns));
  stats.rate_hz = static_cast<double>(kNsPerSecond) / median_interval_ns;
}

/// Duplicates (second frame on an edge, repeated number) and drops (edges without a frame inside the
/// paired span, skipped device numbers).
std::vector<bool> countPairs(const EdgePairing& pairing, std::size_t edge_count, const FrameNumberCounts& numbers,
                             SyncReport& report) {
  const std::size_t frame_count = pairing.edge_of_frame.size();
  std::vector<std::size_t> uses(edge_count, 0);
  std::vector<bool> duplicate(frame_count, false);
  for (std::size_t i = 0; i < frame_count; ++i) {
    const std::ptrdiff_t edge = pairing.edge_of_frame[i];
    if (edge == kNoEdge) {
      ++report.frames.without_edge;
    } else {
      ++report.frames.paired_with_edge;
      if (uses[static_cast<std::size_t>(edge)]++ > 0) {
        duplicate[i] = true;
        ++report.duplicated.frames_on_one_edge;
      }
    }
    if (numbers.is_repeat[i]) duplicate[i] = true;
  }
  report.duplicated.repeated_frame_numbers = numbers.repeated;

  const auto first = std::find_if(uses.begin(), uses.end(), [](std::size_t n) { return n > 0; });
  const auto last = std::find_if(uses.rbegin(), uses.rend(), [](std::size_t n) { return n > 0; });
  std::size_t paired_edges = 0;
  if (first != uses.end()) {
    const auto span_end = last.base();
    report.dropped.edges_without_frame = static_cast<std::size_t>(std::count(first, span_end, std::size_t{0}));
    paired_edges = static_cast<std::size_t>(span_end - first) - report.dropped.edges_without_frame;
  }
  report.dropped.frame_number_gaps = numbers.skipped;
  report.dropped.dropped = std::max<std::uint64_t>(report.dropped.edges_without_frame, numbers.skipped);
  if (paired_edges > 0 || numbers.present) {
    const auto delivered = static_cast<std::size_t>(std::count(duplicate.begin(), duplicate.end(), false));
    report.dropped.fraction =
        static_cast<double>(report.dropped.dropped) / static_cast<double>(delivered + report.dropped.dropped);
  }
  return duplicate;
}

/// The four stream pairs, duplicates left out.
std::vector<StreamStats> measureStreams(const std::vector<CameraFrameTimes>& frames,
                                        const std::vector<std::int64_t>& edge_t_ns, const EdgePairing& pairing,
                                        const std::vector<bool>& duplicate) {
  struct Series {
    std::vector<std::int64_t> t_ns;
    std::vector<double> offset_ns;
    void add(std::int64_t t, std::int64_t a, std::int64_t b) {
      t_ns.push_back(t);
      offset_ns.push_back(static_cast<double>(a - b));
    }
  };
  Series frame_edge, kernel_edge, event_edge, frame_kernel;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (duplicate[i]) continue;
    const CameraFrameTimes& frame = frames[i];
    if (pairing.edge_of_frame[i] != kNoEdge) {
      const std::int64_t edge_ns = edge_t_ns[static_cast<std::size_t>(pairing.edge_of_frame[i])];
      frame_edge.add(edge_ns, frame.t_ns, edge_ns);
      if (frame.kernel_mid_ns != 0) kernel_edge.add(edge_ns, frame.kernel_mid_ns, edge_ns);
      if (frame.device_event_ns != 0) event_edge.add(edge_ns, frame.device_event_ns, edge_ns);
    }
    if (frame.kernel_mid_ns != 0) frame_kernel.add(frame.t_ns, frame.t_ns, frame.kernel_mid_ns);
  }
  std::vector<StreamStats> streams;
  streams.push_back(
      measureStream(std::string(kFrameMinusEdge), std::move(frame_edge.t_ns), std::move(frame_edge.offset_ns)));
  streams.push_back(
      measureStream(std::string(kKernelMinusEdge), std::move(kernel_edge.t_ns), std::move(kernel_edge.offset_ns)));
  streams.push_back(
      measureStream(std::string(kDeviceEventMinusEdge), std::move(event_edge.t_ns), std::move(event_edge.offset_ns)));
  streams.push_back(
      measureStream(std::string(kFrameMinusKernel), std::move(frame_kernel.t_ns), std::move(frame_kernel.offset_ns)));
  return streams;
}

}  // namespace

SyncReport analyse(const SyncInput& input, const SyncCheckOptions& options) {
  options.validate();
  SyncReport report;
  ProblemLog problems(report.problems);

  const std::vector<std::int64_t> edge_t_ns = usableEdges(input.edges, options.edge_polarity, report.edges, problems);
  countFrames(input.frames, report.frames, problems);
  const FrameNumberCounts numbers = countFrameNumbers(input.frames, options.frame_number_bits, problems);
  report.frames.frame_numbers_present = numbers.present;
  report.frames.frame_number_backwards = numbers.backwards;

  std::vector<std::int64_t> frame_t_ns(input.frames.size());
  for (std::size_t i = 0; i < input.frames.size(); ++i) frame_t_ns[i] = input.frames[i].t_ns;
  const double period_ns =
      std::isfinite(report.edges.period_ns) ? report.edges.period_ns : static_cast<double>(options.framePeriodNs());
  const EdgePairing pairing = pairFramesWithEdges(frame_t_ns, edge_t_ns, period_ns, options.pairing_window_fraction);

  const std::vector<bool> duplicate = countPairs(pairing, edge_t_ns.size(), numbers, report);
  report.streams = measureStreams(input.frames, edge_t_ns, pairing, duplicate);
  report.imu = measureImu(input.imu_t_ns, problems);
  report.clock_residuals = measureClockResiduals(input.clock_residuals, problems);
  report.checks = evaluateChecks(report, options);
  report.passed =
      std::all_of(report.checks.begin(), report.checks.end(), [](const CheckResult& c) { return c.passed; });
  return report;
}

}  // namespace vifusion::synccheck
