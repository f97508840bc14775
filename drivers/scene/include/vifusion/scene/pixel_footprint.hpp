#pragma once
// Ray differentials (Igehy, "Tracing Ray Differentials", SIGGRAPH 1999) on the scene's planar faces:
// how far a hit's texture coordinates move per pixel of image motion. The renderer sizes the texture
// filter (texture.hpp) with it, so each pixel's colour is the texture averaged over the patch of
// surface the pixel sees.

#include <Eigen/Core>

#include "vifusion/scene/box.hpp"

namespace vifusion::scene {

/// ∂st_m/∂(u, v) [m/px] at `hit`, found on the ray origin + t·direction_W (hit.t is that t), where
/// ddirection_du_W and ddirection_dv_W [1/px] are the derivatives of direction_W with respect to the
/// pixel coordinates (for directions with unit camera z: R_W_C.col(0)/fx and R_W_C.col(1)/fy). Exact
/// for the plane of the face: the hit slides along the face as the ray turns.
Eigen::Matrix2d stJacobian(const SurfaceHit& hit, const Eigen::Vector3d& direction_W,
                           const Eigen::Vector3d& ddirection_du_W, const Eigen::Vector3d& ddirection_dv_W);

}  // namespace vifusion::scene
