#pragma once
// A built-in RGB-D frame rendered analytically (no files needed): a checkered back wall, a floor
// and a shaded sphere, seen by a Kinect-like pinhole camera. Used by the GPU self-check until the
// synthetic benchmark sequences replace it.

#include <cstdint>

#include "vifusion/core/image.hpp"
#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/preprocess/pixel_types.hpp"

namespace vifusion::cli {

struct SyntheticFrame {
  PinholeCamera camera;
  Image<std::uint16_t> depth_mm;  ///< depth along the optical axis [mm], 0 = nothing hit
  Image<preprocess::Rgb8> rgb;
};

/// Renders the scene at width × height (width even), focal length scaled from 525 px at 640.
SyntheticFrame renderSyntheticFrame(int width, int height);

}  // namespace vifusion::cli
