#pragma once
// Z16 depth frames → depth images. Z16 is 16-bit little-endian, one value per pixel, 0 = no depth; one unit
// is the DS4 "depth units" extension-unit control in µm (default 1000 µm → 1 mm; uvc_xu.hpp reads it), so
// metres = value × depthScaleMetres(units).
//
// The ZR300/R200 depth node delivers 628×469: 468 depth rows and the metadata row (ds_metadata.hpp).
// librealsense shows it padded by 6 px on every side (640×480): zero the 640×480 image once, then convert
// into its centre, ImageView(image.data() + 6·640 + 6, 628, 468, 640).

#include <cstdint>
#include <span>

#include "vifusion/core/image.hpp"
#include "vifusion/v4l2/problem_text.hpp"

namespace vifusion::v4l2 {

inline constexpr double kMetresPerMicrometre = 1e-6;

/// Metres per depth unit for a depth-units control value [µm per unit].
constexpr double depthScaleMetres(std::uint32_t depth_units_um) {
  return static_cast<double>(depth_units_um) * kMetresPerMicrometre;
}

/// Copies the first depth.height rows × depth.width values of a Z16 frame (rows `bytes_per_line` apart) into
/// the caller's image view. No allocation. False with `problem` set when the frame is too short for the view.
bool z16ToDepth(std::span<const std::uint8_t> frame, std::uint32_t bytes_per_line, ImageView<std::uint16_t> depth,
                ProblemText& problem);

}  // namespace vifusion::v4l2
