#pragma once
// Pairs camera frames with sync-line edges despite an unknown offset (up to ± half a frame period) and
// drift; the method is described in analyse.hpp.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "vifusion/synccheck/robust_line_fit.hpp"

namespace vifusion::synccheck {

inline constexpr std::ptrdiff_t kNoEdge = -1;

struct EdgePairing {
  /// Per frame (delivery order): the index of its edge in the edge list, or kNoEdge.
  std::vector<std::ptrdiff_t> edge_of_frame;
  /// The line through (edge time − fit_origin_ns [s], stamp − edge [ns]) the re-pairing used, refitted.
  LineFit fit;
  std::int64_t fit_origin_ns = 0;  ///< the first paired edge's time [ns]
};

/// Frames within `frames_used` for the coarse offset: ~2 s at 30 Hz, long enough to average jitter,
/// short enough that drift (40 ppm × 2 s = 80 µs) does not smear it.
inline constexpr std::size_t kCoarseFrames = 64;
/// How much of each accepted residual the tracked offset takes (an exponential average over ~16 frames).
inline constexpr double kTrackingGain = 1.0 / 16.0;

/// `frame_t_ns`: the stamps, delivery order, any values. `edge_t_ns`: strictly increasing. `period_ns`:
/// the frame period (> 0); `window_fraction`: the pairing window's half-width in periods, (0, 0.5).
EdgePairing pairFramesWithEdges(std::span<const std::int64_t> frame_t_ns, std::span<const std::int64_t> edge_t_ns,
                                double period_ns, double window_fraction);

}  // namespace vifusion::synccheck
