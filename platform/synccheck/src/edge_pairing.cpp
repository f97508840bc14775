#include "edge_pairing.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sample_stats.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion::synccheck {
namespace {

/// Index of the edge nearest `t_ns`. Precondition: edges not empty.
std::size_t nearestEdge(std::span<const std::int64_t> edges, double t_ns) {
  const auto after = std::lower_bound(edges.begin(), edges.end(), t_ns,
                                      [](std::int64_t edge, double t) { return static_cast<double>(edge) < t; });
  if (after == edges.begin()) return 0;
  const auto index = static_cast<std::size_t>(after - edges.begin());
  if (after == edges.end()) return index - 1;
  return t_ns - static_cast<double>(edges[index - 1]) <= static_cast<double>(edges[index]) - t_ns ? index - 1 : index;
}

/// Stamp − nearest edge over the first frames, as a phase of the period: the circular mean does not split
/// when the offset sits at ± half a period; then the median of the differences unwrapped around it.
double coarseOffsetNs(std::span<const std::int64_t> frames, std::span<const std::int64_t> edges, double period_ns) {
  const std::size_t used = std::min(frames.size(), kCoarseFrames);
  std::vector<double> differences(used);
  double sum_sin = 0.0, sum_cos = 0.0;
  for (std::size_t i = 0; i < used; ++i) {
    const double t = static_cast<double>(frames[i]);
    differences[i] = t - static_cast<double>(edges[nearestEdge(edges, t)]);
    const double phase_rad = 2.0 * std::numbers::pi * differences[i] / period_ns;
    sum_sin += std::sin(phase_rad);
    sum_cos += std::cos(phase_rad);
  }
  const double circular_mean_ns = std::atan2(sum_sin, sum_cos) * period_ns / (2.0 * std::numbers::pi);
  for (double& d : differences) d = circular_mean_ns + std::remainder(d - circular_mean_ns, period_ns);
  return median(std::move(differences));
}

/// Pairs frame i with the edge nearest stamp − predicted(i), if the residual is within the window.
template <class Predict, class Accept>
void pairAround(std::span<const std::int64_t> frames, std::span<const std::int64_t> edges, double window_ns,
                Predict&& predicted_offset_ns, Accept&& accept, std::vector<std::ptrdiff_t>& edge_of_frame) {
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const double t = static_cast<double>(frames[i]);
    const double predicted = predicted_offset_ns(t);
    const std::size_t edge = nearestEdge(edges, t - predicted);
    const double residual = t - static_cast<double>(edges[edge]) - predicted;
    if (std::abs(residual) <= window_ns) {
      edge_of_frame[i] = static_cast<std::ptrdiff_t>(edge);
      accept(residual);
    } else {
      edge_of_frame[i] = kNoEdge;
    }
  }
}

LineFit fitPairs(std::span<const std::int64_t> frames, std::span<const std::int64_t> edges,
                 const std::vector<std::ptrdiff_t>& edge_of_frame, std::int64_t& first_edge_ns) {
  std::vector<double> x_s, y_ns;
  first_edge_ns = 0;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (edge_of_frame[i] == kNoEdge) continue;
    const std::int64_t edge_ns = edges[static_cast<std::size_t>(edge_of_frame[i])];
    if (x_s.empty()) first_edge_ns = edge_ns;
    x_s.push_back(nsToSeconds(edge_ns - first_edge_ns));
    y_ns.push_back(static_cast<double>(frames[i] - edge_ns));
  }
  return fitRobustLine(x_s, y_ns);
}

}  // namespace

EdgePairing pairFramesWithEdges(std::span<const std::int64_t> frame_t_ns, std::span<const std::int64_t> edge_t_ns,
                                double period_ns, double window_fraction) {
  EdgePairing pairing;
  pairing.edge_of_frame.assign(frame_t_ns.size(), kNoEdge);
  if (edge_t_ns.empty() || frame_t_ns.empty()) return pairing;
  const double window_ns = window_fraction * period_ns;

  double tracked_ns = coarseOffsetNs(frame_t_ns, edge_t_ns, period_ns);
  pairAround(
      frame_t_ns, edge_t_ns, window_ns, [&](double) { return tracked_ns; },
      [&](double residual) { tracked_ns += kTrackingGain * residual; }, pairing.edge_of_frame);

  pairing.fit = fitPairs(frame_t_ns, edge_t_ns, pairing.edge_of_frame, pairing.fit_origin_ns);
  if (!pairing.fit.valid()) return pairing;  // fewer than two distinct pairs: the tracking stands
  // The line predicts each frame's offset without the tracker's lag; x is taken at the stamp (the offset
  // is < a period, which moves the prediction by < drift × 33 ms: nanoseconds).
  pairAround(
      frame_t_ns, edge_t_ns, window_ns,
      [&](double t) { return pairing.fit.at(nsToSeconds(static_cast<std::int64_t>(t) - pairing.fit_origin_ns)); },
      [](double) {}, pairing.edge_of_frame);
  std::int64_t refit_origin_ns = 0;
  const LineFit refit = fitPairs(frame_t_ns, edge_t_ns, pairing.edge_of_frame, refit_origin_ns);
  if (refit.valid()) pairing.fit = refit, pairing.fit_origin_ns = refit_origin_ns;
  return pairing;
}

}  // namespace vifusion::synccheck
