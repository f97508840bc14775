#pragma once
// One V4L2 capture node (the ZR300's depth or colour node) streamed with MMAP buffers through a DeviceIo.
//
//   start():  open O_RDWR|O_NONBLOCK → VIDIOC_QUERYCAP (VIDEO_CAPTURE + STREAMING required) → VIDIOC_S_FMT
//             (FIELD_NONE; the granted format must equal the request) → VIDIOC_S_PARM (1/fps, checked) →
//             VIDIOC_REQBUFS(MMAP) → VIDIOC_QUERYBUF + mmap each → VIDIOC_QBUF all → VIDIOC_STREAMON.
//             Any failure undoes what was done and throws (DeviceError when a call failed, with its errno).
//   next():   DQBUF, or poll then DQBUF → one outcome: a frame (borrowed until released), a timeout, a rejected
//             buffer (error-flagged, short, or an unusable timestamp: counted, requeued, reason in
//             lastProblem()), unplugged (ENODEV/EIO/…: no exception, the caller waits for hotplug), or another
//             error. Never throws, never allocates.
//   stop():   STREAMOFF → munmap all → REQBUFS(0) → close; errors are ignored, so it is safe after an unplug.
//             Also run by the destructor. Frames still borrowed become inert (their release does nothing) and
//             their bytes are no longer mapped.
//
// Dropped frames are counted from gaps in the V4L2 sequence (frames the driver had no buffer for) and, when
// the caller reports the camera's own embedded counter (noteEmbeddedFrameCounter), from gaps there (frames
// lost before the host). Buffers flagged V4L2_BUF_FLAG_ERROR are counted and requeued unseen.
//
// Threading: one thread calls start/next/stop and releases frames; stats() from the same thread.
// Restrictions: no VIDIOC_STREAMON retries (librealsense retries 10× at 100 ms; here the caller's
// hotplug/backoff loop restarts the stream instead).

#include <linux/videodev2.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "vifusion/v4l2/device_io.hpp"
#include "vifusion/v4l2/frame_counter_gaps.hpp"
#include "vifusion/v4l2/mid_exposure_clock.hpp"
#include "vifusion/v4l2/problem_text.hpp"
#include "vifusion/v4l2/v4l2_stream_options.hpp"

namespace vifusion::v4l2 {

class V4l2Stream;

/// One dequeued buffer as the caller sees it. The bytes live in the driver's MMAP buffer.
struct FrameView {
  std::span<const std::uint8_t> bytes;  ///< the buffer's valid bytes (v4l2_buffer.bytesused of them)
  std::uint32_t bytes_per_line = 0;     ///< row stride of the granted format [bytes]
  std::uint32_t sequence = 0;           ///< V4L2 sequence number (0 for the first frame after STREAMON)
  std::int64_t t_stamp_ns = 0;          ///< kernel timestamp, CLOCK_MONOTONIC [ns] (the kernel reports µs)
  std::int64_t t_mid_exposure_ns = 0;   ///< mid-exposure time, CLOCK_MONOTONIC [ns] (see MidExposureClock)
  std::uint32_t flags = 0;              ///< v4l2_buffer.flags as dequeued
  int buffer_index = -1;                ///< which MMAP buffer
};

/// A frame on loan from the stream: valid until release(), destruction, or the stream's stop(). Move-only.
/// Releasing queues the buffer back to the driver (VIDIOC_QBUF); a failure there is counted by the stream.
class BorrowedFrame {
 public:
  BorrowedFrame() = default;
  BorrowedFrame(BorrowedFrame&& other) noexcept { *this = static_cast<BorrowedFrame&&>(other); }
  BorrowedFrame& operator=(BorrowedFrame&& other) noexcept;
  BorrowedFrame(const BorrowedFrame&) = delete;
  BorrowedFrame& operator=(const BorrowedFrame&) = delete;
  ~BorrowedFrame() { release(); }

  explicit operator bool() const { return stream_ != nullptr; }
  const FrameView& view() const { return view_; }
  /// Gives the buffer back now; afterwards this object is empty. Idempotent.
  void release() noexcept;

 private:
  friend class V4l2Stream;
  BorrowedFrame(V4l2Stream* stream, const FrameView& view, std::uint64_t generation)
      : stream_(stream), view_(view), generation_(generation) {}

  V4l2Stream* stream_ = nullptr;
  FrameView view_;
  std::uint64_t generation_ = 0;
};

enum class NextStatus {
  kFrame,      ///< NextResult::frame holds a frame
  kTimeout,    ///< nothing arrived within the timeout
  kRejected,   ///< a buffer arrived but was unusable; counted, requeued, reason in lastProblem()
  kUnplugged,  ///< the device is gone; stop() and wait for it to come back
  kError,      ///< anything else (reason in lastProblem()); the stream may still work
};
const char* nextStatusName(NextStatus status);

struct NextResult {
  NextStatus status = NextStatus::kTimeout;
  BorrowedFrame frame;  ///< non-empty only for kFrame
};

/// Counters since construction (they survive stop/start).
struct V4l2StreamStats {
  std::int64_t frames = 0;                        ///< delivered as kFrame
  std::int64_t sequence_gap_frames = 0;           ///< missing from the V4L2 sequence (lost in driver or kernel)
  std::int64_t sequence_regressions = 0;          ///< V4L2 sequence not after the previous one
  std::int64_t embedded_gap_frames = 0;           ///< missing from the caller-reported embedded counter
  std::int64_t embedded_counter_regressions = 0;  ///< embedded counter not after the previous one
  std::int64_t error_flagged_buffers = 0;         ///< V4L2_BUF_FLAG_ERROR
  std::int64_t short_buffers = 0;                 ///< bytesused below the granted sizeimage (or above length)
  std::int64_t refused_timestamps = 0;            ///< see MidExposureClock
  std::int64_t timeouts = 0;
  std::int64_t unplugs = 0;
  std::int64_t errors = 0;  ///< kError outcomes and failed requeues
};

/// What the driver granted at start().
struct GrantedFormat {
  std::uint32_t fourcc = 0;
  int width_px = 0;
  int height_px = 0;
  std::uint32_t bytes_per_line = 0;  ///< row stride [bytes]
  std::uint32_t size_image = 0;      ///< bytes of one full frame
  int buffer_count = 0;              ///< MMAP buffers the driver allocated
};

class V4l2Stream {
 public:
  /// Validates the options (throws vifusion::Error naming the bad field); touches no device.
  V4l2Stream(DeviceIo& io, const V4l2StreamOptions& options);
  ~V4l2Stream() { stop(); }
  V4l2Stream(const V4l2Stream&) = delete;
  V4l2Stream& operator=(const V4l2Stream&) = delete;

  /// @throws DeviceError (a call failed; errorNumber(), deviceGone()) or vifusion::Error (the node cannot do
  ///         what was asked: missing capability, format or rate changed by the driver), naming the node.
  void start();
  /// Waits up to timeout_ns (≥ 0; rounded up to whole ms for poll) for the next buffer.
  NextResult next(std::int64_t timeout_ns);
  void stop() noexcept;

  bool streaming() const { return state_ == State::kStreaming; }
  bool unplugged() const { return state_ == State::kUnplugged; }
  /// The file descriptor while started (for UVC extension-unit controls on this node), else −1.
  int fd() const { return fd_; }
  const GrantedFormat& format() const { return format_; }
  const V4l2StreamOptions& options() const { return options_; }
  V4l2StreamStats stats() const;
  /// Why the last kRejected/kUnplugged/kError outcome happened: names the stream, the field and the value.
  std::string_view lastProblem() const { return problem_.view(); }

  /// Exposure and readout for the frames that follow (auto-exposure changes them).
  void setExposureTiming(const ExposureTiming& timing) { timing_ = timing; }
  /// The camera's own frame counter of the frame just received (decoded from its embedded metadata): gaps
  /// are counted as dropped frames, separately from V4L2 sequence gaps. Returns this step.
  FrameCounterGaps::Step noteEmbeddedFrameCounter(std::uint32_t counter) { return embedded_gaps_.observe(counter); }

 private:
  friend class BorrowedFrame;
  enum class State { kStopped, kStreaming, kUnplugged };
  enum class SlotState { kUnused, kQueued, kWithCaller };
  struct BufferSlot {
    std::uint8_t* data = nullptr;  ///< mapping, or nullptr
    std::size_t length = 0;        ///< mapped bytes
    SlotState state = SlotState::kUnused;
  };
  enum class Dequeue { kGot, kNothingReady, kFailed };

  void openAndCheckCapabilities();
  void negotiateFormat();
  void negotiateFrameRate();
  void allocateAndMapBuffers();
  void queueAllAndStreamOn();

  Dequeue dequeue(v4l2_buffer& buffer);
  NextResult handleBuffer(const v4l2_buffer& buffer);
  NextResult reject(int index);  ///< requeues a buffer the caller will not see
  NextResult fail(const char* call, int error_number);
  bool requeue(int index);
  void releaseFrame(int index, std::uint64_t generation) noexcept;

  DeviceIo& io_;
  V4l2StreamOptions options_;
  ExposureTiming timing_;
  State state_ = State::kStopped;
  int fd_ = -1;
  bool buffers_requested_ = false;
  bool stream_on_ = false;
  GrantedFormat format_;
  std::array<BufferSlot, kMaxStreamingBuffers> slots_{};
  int queued_count_ = 0;
  std::uint64_t generation_ = 1;  ///< bumped by stop(), so frames borrowed before it stay inert
  FrameCounterGaps sequence_gaps_;
  FrameCounterGaps embedded_gaps_;
  MidExposureClock mid_exposure_clock_;
  V4l2StreamStats counts_;  ///< the counters not kept by the gap trackers and the clock
  ProblemText problem_;
};

}  // namespace vifusion::v4l2
