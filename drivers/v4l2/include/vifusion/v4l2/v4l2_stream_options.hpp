#pragma once
// What one V4L2 capture node is asked to stream. Sizes are those the node delivers: for the ZR300/R200 depth
// node that includes the trailing metadata row (Z16 628×469 = 468 depth rows + 1 "dinghy" row, sensors.md
// §1.2); cropping or padding to the pipeline's 640×480 is the caller's job.

#include <linux/videodev2.h>

#include <cstdint>
#include <string>

#include "vifusion/v4l2/fourcc.hpp"
#include "vifusion/v4l2/mid_exposure_clock.hpp"

namespace vifusion::v4l2 {

/// Fewest MMAP buffers that can stream: one being filled while the caller holds another.
inline constexpr int kMinStreamingBuffers = 2;
/// Most buffers a V4L2 queue hands out (VIDEO_MAX_FRAME); the stream keeps a fixed table of this size.
inline constexpr int kMaxStreamingBuffers = VIDEO_MAX_FRAME;
/// Largest width or height accepted [px]: far above any UVC camera, low enough that sizes cannot overflow.
inline constexpr int kMaxFrameDimensionPx = 16384;
/// Highest frame rate accepted [Hz]; the ZR300 tops out at 90 Hz (IR/depth).
inline constexpr int kMaxFrameRateHz = 1000;

struct V4l2StreamOptions {
  std::string label = "camera";  ///< names the stream in every message ("depth", "colour")
  std::string node_path;         ///< the capture node, e.g. "/dev/video1"; required
  std::uint32_t fourcc = kFourccYuyv;
  int width_px = 640;    ///< delivered width, [1, kMaxFrameDimensionPx]
  int height_px = 480;   ///< delivered height including embedded metadata rows, [1, kMaxFrameDimensionPx]
  int fps = 30;          ///< frame rate asked for with VIDIOC_S_PARM, [1, kMaxFrameRateHz]
  int buffer_count = 4;  ///< MMAP buffers from the capacity plan, [kMinStreamingBuffers, kMaxStreamingBuffers]
  /// Exposure at start; follow auto-exposure with V4l2Stream::setExposureTiming(). exposure_ns in
  /// [0, 1 s / fps] (a frame cannot integrate longer than its period), readout_ns in the same range.
  ExposureTiming timing;

  /// @throws vifusion::Error naming the field that is out of range, and its value.
  void validate() const;
};

}  // namespace vifusion::v4l2
