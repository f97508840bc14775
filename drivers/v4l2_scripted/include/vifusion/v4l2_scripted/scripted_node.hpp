#pragma once
// What one scripted V4L2 capture node offers and the frames it will produce.
//
// Frames follow a schedule on the ManualClock: frame k is complete (ready to dequeue) at
//   arrival(k) = first_arrival_ns + k · period_ns        (period_ns 0: 1 s / the granted fps, rounded)
// for k < frame_count (−1: endless). After VIDIOC_STREAMON at time s the node serves the frames with
// arrival(k) > s, with V4L2 sequence numbers 0, 1, 2, … counted from STREAMON as uvcvideo does. Each arrival
// takes the oldest queued buffer and asks the producer to fill it; with no queued buffer the frame is lost in
// the "driver" and its sequence number is skipped. The producer can also make a frame lost before the host
// (sequence skipped, no buffer used), flag a buffer V4L2_BUF_FLAG_ERROR, change the timestamp, its flags or
// bytesused. Content is derived from the absolute frame index k, so depth and colour nodes on one schedule
// produce matching frames whenever each was started.

#include <linux/videodev2.h>

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace vifusion::v4l2_scripted {

/// One frame size the node offers, with its rates.
struct ScriptedFormat {
  std::uint32_t fourcc = V4L2_PIX_FMT_YUYV;
  int width_px = 640;
  int height_px = 480;
  std::uint32_t bytes_per_line = 0;  ///< 0: tightly packed
  std::vector<int> fps = {30};       ///< rates offered at this size [Hz]
};

/// One UVC extension-unit control and its value (its size is the value's size).
struct ScriptedControl {
  std::uint8_t unit = 0;
  std::uint8_t selector = 0;
  std::vector<std::uint8_t> value;
  bool writable = true;  ///< SET_CUR on a read-only control fails with EIO
};

/// What the producer is asked to fill.
struct ScriptedFrameRequest {
  std::int64_t frame_index = 0;     ///< k on the node's schedule
  std::int64_t arrival_ns = 0;      ///< when the frame completes on the manual clock
  std::uint32_t sequence = 0;       ///< the V4L2 sequence it will carry
  v4l2_pix_format format{};         ///< the granted format
  std::span<std::uint8_t> payload;  ///< the MMAP buffer (sizeimage bytes visible; zero-filled once at REQBUFS)
};

/// What the producer decides; pre-filled with the defaults shown.
struct ScriptedFrame {
  std::int64_t t_stamp_ns = 0;  ///< reported timestamp (default arrival_ns); V4L2 reports whole µs (floor)
  std::uint32_t timestamp_flags = V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC | V4L2_BUF_FLAG_TSTAMP_SRC_SOE;
  bool error = false;            ///< deliver with V4L2_BUF_FLAG_ERROR
  bool lost = false;             ///< lost before the host: sequence skipped, the buffer stays queued
  std::uint32_t bytes_used = 0;  ///< default sizeimage
};

/// Fills one frame. Runs under the device's lock: it must not call back into the device. It runs on the
/// thread that advanced time (a poll, DQBUF or any ioctl), so it should not allocate either, if the caller's
/// no-allocation checks are to hold.
using FrameProducer = std::function<void(const ScriptedFrameRequest&, ScriptedFrame&)>;

struct FrameSchedule {
  std::int64_t first_arrival_ns = 0;  ///< arrival of frame 0 on the manual clock
  std::int64_t period_ns = 0;         ///< 0: 1 s / granted fps
  std::int64_t frame_count = -1;      ///< frames in the script; −1 endless
  FrameProducer produce;              ///< required
};

struct ScriptedNodeConfig {
  std::string path;  ///< e.g. "/dev/video1"
  std::string driver = "uvcvideo";
  std::string card = "RealSense ZR300 (scripted)";  ///< QUERYCAP keeps 31 characters
  std::string bus_info = "usb-scripted-1";
  std::uint32_t device_caps = V4L2_CAP_VIDEO_CAPTURE | V4L2_CAP_STREAMING;
  std::vector<ScriptedFormat> formats;  ///< formats[0] is the default a driver falls back to
  int max_buffers = VIDEO_MAX_FRAME;    ///< REQBUFS grants at most this many
  FrameSchedule schedule;
  std::vector<ScriptedControl> controls;
};

/// Counters of the node instance that is plugged in now.
struct ScriptedNodeStats {
  std::int64_t arrivals = 0;           ///< scheduled frames that came while streaming
  std::int64_t filled = 0;             ///< put into a buffer
  std::int64_t dropped_no_buffer = 0;  ///< no queued buffer at arrival
  std::int64_t lost_by_script = 0;     ///< producer said lost
  std::int64_t dequeued = 0;
  std::int64_t queued = 0;  ///< successful QBUFs
  bool streaming = false;
  int buffers = 0;
  int mapped_buffers = 0;
};

}  // namespace vifusion::v4l2_scripted
