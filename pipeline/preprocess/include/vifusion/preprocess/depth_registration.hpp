#pragma once
// Depth registered to the colour camera. On an RGB-D camera whose depth and colour come from two
// cameras (ZR300: depth from the IR stereo pair, colour from a third imager beside it) a depth
// pixel and the colour pixel with the same (u, v) see different points; the pipeline wants both in
// the colour camera's pixels. DepthRegistration is the calibration that maps one onto the other;
// registerDepthToColourCpu is the CPU reference of shaders/register_depth.comp.
//
// The warp (both implementations): back-project every valid depth pixel, move it into the colour
// frame, project it and round to the nearest colour pixel; where several land on one pixel the
// smallest depth wins (z-buffer: the nearer surface occludes the farther one); pixels nothing lands
// on stay 0 (invalid). Holes are left as holes, not splatted over 2 × 2 or filled: every later stage
// treats 0 as "no measurement", while a splat would paint foreground depth onto background pixels
// next to every depth edge (the footprint grows on the side the baseline uncovers), which biases ICP
// and fusion exactly where the geometry matters. Where the colour camera samples more densely than
// the depth camera (colour focal length > depth focal length) the holes form a regular pattern of
// single missing pixels: no vertex there and no normal next to it (the depth pyramid only skips them
// as neighbours). Configure the colour stream no denser than the depth stream to avoid them.
//
// Lens distortion is not modelled (PinholeCamera): the depth stream is rectified by the device, and
// the colour image must be undistorted before it reaches the pipeline (or its distortion accepted).

#include <cstdint>

#include "vifusion/core/image.hpp"
#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/preprocess/kernel_params.hpp"

namespace vifusion::preprocess {

/// Largest accepted |t_C_D| [m]: both cameras sit on one board, centimetres apart; a metre is a
/// unit error (millimetres given as metres), not a rig.
inline constexpr double kMaxRegistrationBaseline_m = 1.0;
/// Largest accepted depth scale [m per unit]: 1 cm per unit is already coarser than any RGB-D sensor
/// (ZR300: 1 mm by default, TUM: 0.2 mm); more is a scale given in the wrong unit.
inline constexpr double kMaxDepthScale_m = 0.01;
/// A T_C_D closer to the identity than this moves no point by a measurable fraction of a pixel
/// (1e-9 rad · 1000 px ≈ 1e-6 px; 1e-9 m at 0.3 m · 1000 px ≈ 3e-6 px), so registration is skipped.
inline constexpr double kIdentityRotation_rad = 1e-9;
inline constexpr double kIdentityTranslation_m = 1e-9;

/// Calibration of a depth camera D against a colour camera C of the same device.
struct DepthRegistration {
  PinholeCamera depth;           ///< D: intrinsics and size of the raw depth image (rectified, no distortion)
  PinholeCamera colour;          ///< C: intrinsics and size of the colour image, and so of the registered depth
  SE3d T_C_D;                    ///< depth → colour: p_C = T_C_D · p_D [m]
  double depth_scale_m = 0.001;  ///< metres per raw depth unit, in (0, kMaxDepthScale_m]: ZR300 default 1 mm

  /// Throws vifusion::Error naming the bad field ("depth registration 'depth.fx' ...").
  void validate() const;

  /// True when registering would change nothing: equal intrinsics and sizes and T_C_D within
  /// kIdentityRotation_rad / kIdentityTranslation_m of the identity. The preprocessing stage then
  /// skips the step.
  bool isIdentity() const;

  /// The shader's push constants (H, e of RegisterDepthParams) in double, rounded to float once.
  RegisterDepthParams kernelParams() const;
};

/// Registers `depth_raw` (depth.width × depth.height, raw units, 0 = invalid) into `registered_raw`
/// (colour.width × colour.height, the same units, 0 = nothing landed). Validates the registration
/// (vifusion::Error) and the view sizes (std::invalid_argument); no allocation. The views must not alias.
void registerDepthToColourCpu(ImageView<const std::uint16_t> depth_raw, const DepthRegistration& registration,
                              ImageView<std::uint16_t> registered_raw);

}  // namespace vifusion::preprocess
