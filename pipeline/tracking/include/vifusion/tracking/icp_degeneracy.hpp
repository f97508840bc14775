#pragma once
// The pose directions point-to-plane ICP cannot see, removed from its normal equations.
//
// ICP constrains a translation e only through the normals of the surfaces in view: its information
// along e is Σ w (n·e)². One plane (a blank wall) leaves the two translations in it and the rotation
// about its normal free; two planes (wall and ceiling) leave their common edge free. Yet noisy and
// quantised depth give those directions a formal information that looks decisive, and a biased one:
// depth quantisation bands are fixed to the camera, so sliding along a wall moves the map's bands
// against the frame's and ICP pulls the estimate back to "no motion" (sim:white_wall, 320×240: the
// pose stood still while the camera moved along the wall at 0.2 m/s). Here a translation direction
// whose share of the ICP weight, λ(H_tt)/tr(H_tt) = Σ w (n·e)² / Σ w, is below min_share is projected
// out of the ICP system, and when two are (one plane) so is the rotation about the remaining normal.
// On sim data the shares are 0.0003–0.003 facing a blank wall, 0.004–0.009 on a wall–ceiling edge,
// and ≥ 0.05 with furniture or a third wall in view.
//
// The system is over the reference camera's left twist [ρ; φ] (translation first), as the ICP shader
// reduces it.

#include "vifusion/reduction/normal_equations.hpp"

namespace vifusion::tracking {

/// Subtracts from `system` (the sum of `icp` and other terms) the ICP part along the directions its
/// surfaces leave unconstrained: with P the projector onto the others, icp.H → P·icp.H·P and
/// icp.b → P·icp.b. Returns the number of directions removed (0–4: up to three translations plus the
/// rotation about a single plane's normal).
int removeUnconstrainedIcpDirections(const NormalEquations6& icp, double min_share, NormalEquations6& system);

}  // namespace vifusion::tracking
