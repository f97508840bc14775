#pragma once
// The timestamp-sync analysis behind `vifusion synccheck`: pairs every camera frame with its sync-line
// edge, measures offset, jitter and drift per stream pair, counts dropped and duplicated frames, IMU rate
// and gaps, summarises the clock mapper's residuals, and judges it all against the options' limits.
//
// PAIRING (edge_pairing.hpp). The offset between a frame's stamp and its edge is unknown (up to ± half a
// frame period) and drifts, so "the nearest edge" is not good enough near half a period. The frame period
// is the median edge interval. (1) Coarse offset: the circular mean of (stamp − nearest edge) over the
// first frames, as a phase of the period, so offsets near ± half a period do not split into two clusters;
// then the median of the differences unwrapped around it. (2) Tracking: frames in delivery order take the
// edge nearest stamp − predicted offset, if within ± pairing_window_fraction·period, and the prediction
// follows the accepted residuals (drift). (3) A robust line (robust_line_fit.hpp) through the pairs;
// (4) every frame re-paired around the line. A frame whose edge is missing finds the neighbour one period
// away, outside the window: unpaired, never mis-paired.
//
// STREAMS. frame_minus_edge (the stamp SLAM used), kernel_minus_edge, device_event_minus_edge (frames that
// have the value), each against the frame's paired edge; frame_minus_kernel for every frame with both.
// The second frame on one edge and a repeated device number count as duplicates and enter no stream.
//
// Bad input (time going backwards, NaN residuals, edges out of order) is counted in the report, never
// thrown; only invalid options throw.

#include "vifusion/synccheck/sync_check_options.hpp"
#include "vifusion/synccheck/sync_input.hpp"
#include "vifusion/synccheck/sync_report.hpp"

namespace vifusion::synccheck {

/// @throws vifusion::Error when `options` are invalid (naming the field); nothing for any input.
SyncReport analyse(const SyncInput& input, const SyncCheckOptions& options = {});

}  // namespace vifusion::synccheck
