#pragma once
// How a frame placed by relocalisation agrees, image to image, with the keyframe it was matched to: the frame's
// block-averaged depth and colour (FernImage) carried into the keyframe's stored ones through the relative pose
// the dense alignment found. It uses neither the map nor that alignment's residuals, so it sees what they cannot:
// a room corner matched to another corner of the same shape agrees in depth and disagrees in colour.
//
// For every frame block with a depth, its centre is back-projected (the input camera's intrinsics scaled to the
// block grid, fern_image.hpp), moved into the keyframe by T_K_C and projected; where it lands on a keyframe
// block with a depth, the pair overlaps, and it agrees when the two depths differ by at most depth_gate_m (the
// caller's association gate). The intensities (Rec. 601 luma) of the agreeing pairs give a normalised
// cross-correlation.

#include <cstdint>

#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/loop/fern_database.hpp"
#include "vifusion/loop/fern_image.hpp"

namespace vifusion::loop {

struct KeyframeAgreement {
  int frame_blocks = 0;    ///< frame blocks with a depth
  int overlap = 0;         ///< of those, landing on a keyframe block with a depth
  int depth_agreeing = 0;  ///< of the overlap, within the depth gate
  /// Normalised cross-correlation of the agreeing pairs' luma, in [−1, 1]; 0 with fewer than two pairs or when
  /// either side varies by less than one grey level (a blank wall: colour cannot tell).
  double luma_ncc = 0.0;
  double frame_luma_std = 0.0;     ///< standard deviation of the frame's luma over those pairs [0, 255]
  double keyframe_luma_std = 0.0;  ///< the same of the keyframe's
};

/// @param frame         the frame's block image (FernFrame::image), encoded by the keyframe's database
/// @param keyframe      the matched keyframe (its stored block images and pose)
/// @param T_K_C         the frame's camera in the keyframe's camera: T_W_K⁻¹·T_W_C
/// @param input_camera  the full-resolution camera the block images were made from
/// @param factor        the block size (FernOptions::downsample_factor), ≥ 1
/// @param depth_gate_m  largest depth difference of an agreeing pair [m], > 0
/// No allocation.
KeyframeAgreement keyframeAgreement(const FernImage& frame, const FernKeyframe& keyframe, const SE3d& T_K_C,
                                    const PinholeCamera& input_camera, int factor, double depth_gate_m);

}  // namespace vifusion::loop
