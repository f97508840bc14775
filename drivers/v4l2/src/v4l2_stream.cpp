#include "vifusion/v4l2/v4l2_stream.hpp"

#include <fcntl.h>
#include <sys/mman.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/v4l2/device_error.hpp"

namespace vifusion::v4l2 {
namespace {

constexpr std::uint32_t kCaptureType = V4L2_BUF_TYPE_VIDEO_CAPTURE;

std::int64_t timevalToNs(const timeval& time) {
  return static_cast<std::int64_t>(time.tv_sec) * kNsPerSecond +
         static_cast<std::int64_t>(time.tv_usec) * kNsPerMicrosecond;
}

/// Timeout for poll(2) [ms], rounded up so a short wait is not turned into a busy spin; capped to int.
int pollTimeoutMs(std::int64_t timeout_ns) {
  constexpr std::int64_t kLongestPollMs = 1'000'000'000;  // ≈ 11.6 days: far beyond any sensible wait
  if (timeout_ns <= 0) return 0;
  const std::int64_t timeout_ms = (timeout_ns + kNsPerMillisecond - 1) / kNsPerMillisecond;
  return static_cast<int>(timeout_ms < kLongestPollMs ? timeout_ms : kLongestPollMs);
}

v4l2_buffer mmapBuffer(int index) {
  v4l2_buffer buffer{};
  buffer.type = kCaptureType;
  buffer.memory = V4L2_MEMORY_MMAP;
  buffer.index = static_cast<std::uint32_t>(index);
  return buffer;
}

/// A fixed-size text field of a kernel struct, which may lack its terminating NUL.
template <std::size_t N>
std::string fieldText(const std::uint8_t (&field)[N]) {
  const char* text = reinterpret_cast<const char*>(field);
  return std::string(text, ::strnlen(text, N));
}

std::string fourccString(std::uint32_t fourcc) { return fourccText(fourcc).data(); }

std::string formatString(std::uint32_t fourcc, std::uint32_t width, std::uint32_t height) {
  return "'" + fourccString(fourcc) + "' " + std::to_string(width) + "x" + std::to_string(height);
}

/// Formats the camera needs that mainline uvcvideo did not know before the RealSense pixel-format patch.
bool needsRealSenseFormatPatch(std::uint32_t fourcc) { return fourcc == kFourccZ16; }

}  // namespace

const char* nextStatusName(NextStatus status) {
  switch (status) {
    case NextStatus::kFrame:
      return "frame";
    case NextStatus::kTimeout:
      return "timeout";
    case NextStatus::kRejected:
      return "rejected";
    case NextStatus::kUnplugged:
      return "unplugged";
    case NextStatus::kError:
      return "error";
  }
  return "unknown";
}

BorrowedFrame& BorrowedFrame::operator=(BorrowedFrame&& other) noexcept {
  if (this != &other) {
    release();
    stream_ = other.stream_;
    view_ = other.view_;
    generation_ = other.generation_;
    other.stream_ = nullptr;
  }
  return *this;
}

void BorrowedFrame::release() noexcept {
  if (stream_ == nullptr) return;
  stream_->releaseFrame(view_.buffer_index, generation_);
  stream_ = nullptr;
}

V4l2Stream::V4l2Stream(DeviceIo& io, const V4l2StreamOptions& options)
    : io_(io), options_(options), timing_(options.timing) {
  options_.validate();
}

// ---- start ----

void V4l2Stream::start() {
  if (fd_ >= 0) {
    throw Error(options_.label + " " + options_.node_path + ": start() while started; stop() first");
  }
  try {
    openAndCheckCapabilities();
    negotiateFormat();
    negotiateFrameRate();
    allocateAndMapBuffers();
    queueAllAndStreamOn();
  } catch (...) {
    stop();
    throw;
  }
  state_ = State::kStreaming;
  sequence_gaps_.reset();
  embedded_gaps_.reset();
  mid_exposure_clock_.reset();
  problem_.clear();
}

void V4l2Stream::openAndCheckCapabilities() {
  const std::string where = options_.label + " " + options_.node_path;
  fd_ = io_.open(options_.node_path.c_str(), O_RDWR | O_NONBLOCK);
  if (fd_ < 0) throw DeviceError(where + ": cannot open", errno);

  v4l2_capability capability{};
  if (io_.ioctl(fd_, VIDIOC_QUERYCAP, &capability) < 0) {
    throw DeviceError(where + ": VIDIOC_QUERYCAP failed (not a V4L2 device?)", errno);
  }
  // device_caps describes this node; capabilities the whole physical device (all its nodes).
  const std::uint32_t caps =
      (capability.capabilities & V4L2_CAP_DEVICE_CAPS) != 0 ? capability.device_caps : capability.capabilities;
  std::string missing;
  if ((caps & V4L2_CAP_VIDEO_CAPTURE) == 0) missing += " VIDEO_CAPTURE";
  if ((caps & V4L2_CAP_STREAMING) == 0) missing += " STREAMING";
  if (!missing.empty()) {
    const bool metadata_node = (caps & V4L2_CAP_META_CAPTURE) != 0;
    throw Error(where + " (driver '" + fieldText(capability.driver) + "', card '" + fieldText(capability.card) +
                "'): missing capability" + missing +
                (metadata_node ? " (this is a metadata node, not the image node)" : ""));
  }
}

void V4l2Stream::negotiateFormat() {
  const std::string where = options_.label + " " + options_.node_path;
  v4l2_format format{};
  format.type = kCaptureType;
  format.fmt.pix.width = static_cast<std::uint32_t>(options_.width_px);
  format.fmt.pix.height = static_cast<std::uint32_t>(options_.height_px);
  format.fmt.pix.pixelformat = options_.fourcc;
  format.fmt.pix.field = V4L2_FIELD_NONE;
  if (io_.ioctl(fd_, VIDIOC_S_FMT, &format) < 0) throw DeviceError(where + ": VIDIOC_S_FMT failed", errno);

  const v4l2_pix_format& granted = format.fmt.pix;
  const auto width = static_cast<std::uint32_t>(options_.width_px);
  const auto height = static_cast<std::uint32_t>(options_.height_px);
  if (granted.pixelformat != options_.fourcc || granted.width != width || granted.height != height) {
    std::string hint;
    if (granted.pixelformat != options_.fourcc && needsRealSenseFormatPatch(options_.fourcc)) {
      hint = " (uvcvideo lacks the RealSense pixel-format patch for '" + fourccString(options_.fourcc) + "')";
    }
    throw Error(where + ": requested " + formatString(options_.fourcc, width, height) + ", driver granted " +
                formatString(granted.pixelformat, granted.width, granted.height) + hint);
  }
  if (granted.field != V4L2_FIELD_NONE) {
    throw Error(where + ": driver granted field order " + std::to_string(granted.field) +
                ", need progressive frames (V4L2_FIELD_NONE)");
  }
  const auto packed_line = static_cast<std::uint32_t>(options_.width_px * bytesPerPixel(options_.fourcc));
  const std::uint32_t bytes_per_line = granted.bytesperline == 0 ? packed_line : granted.bytesperline;
  if (bytes_per_line < packed_line) {
    throw Error(where + ": driver granted bytesperline " + std::to_string(bytes_per_line) + ", below the " +
                std::to_string(packed_line) + " bytes of one row");
  }
  const std::uint64_t frame_bytes = static_cast<std::uint64_t>(bytes_per_line) * height;
  if (granted.sizeimage < frame_bytes) {
    throw Error(where + ": driver granted sizeimage " + std::to_string(granted.sizeimage) + ", below the " +
                std::to_string(frame_bytes) + " bytes of one frame");
  }
  format_.fourcc = granted.pixelformat;
  format_.width_px = options_.width_px;
  format_.height_px = options_.height_px;
  format_.bytes_per_line = bytes_per_line;
  format_.size_image = static_cast<std::uint32_t>(frame_bytes);
}

void V4l2Stream::negotiateFrameRate() {
  const std::string where = options_.label + " " + options_.node_path;
  v4l2_streamparm parameters{};
  parameters.type = kCaptureType;
  parameters.parm.capture.timeperframe.numerator = 1;
  parameters.parm.capture.timeperframe.denominator = static_cast<std::uint32_t>(options_.fps);
  if (io_.ioctl(fd_, VIDIOC_S_PARM, &parameters) < 0) throw DeviceError(where + ": VIDIOC_S_PARM failed", errno);
  if ((parameters.parm.capture.capability & V4L2_CAP_TIMEPERFRAME) == 0) {
    throw Error(where + ": the driver cannot set the frame rate (no V4L2_CAP_TIMEPERFRAME)");
  }
  const v4l2_fract granted = parameters.parm.capture.timeperframe;
  // Exactly 1/fps s per frame: numerator·fps == denominator (2/60 is accepted as 1/30).
  if (granted.numerator == 0 ||
      static_cast<std::uint64_t>(granted.numerator) * static_cast<std::uint64_t>(options_.fps) != granted.denominator) {
    throw Error(where + ": requested 1/" + std::to_string(options_.fps) + " s per frame, driver granted " +
                std::to_string(granted.numerator) + "/" + std::to_string(granted.denominator) + " s");
  }
}

void V4l2Stream::allocateAndMapBuffers() {
  const std::string where = options_.label + " " + options_.node_path;
  v4l2_requestbuffers request{};
  request.count = static_cast<std::uint32_t>(options_.buffer_count);
  request.type = kCaptureType;
  request.memory = V4L2_MEMORY_MMAP;
  if (io_.ioctl(fd_, VIDIOC_REQBUFS, &request) < 0) {
    throw DeviceError(where + ": VIDIOC_REQBUFS(" + std::to_string(options_.buffer_count) + ", MMAP) failed", errno);
  }
  buffers_requested_ = true;
  if (request.count < static_cast<std::uint32_t>(kMinStreamingBuffers) ||
      request.count > static_cast<std::uint32_t>(kMaxStreamingBuffers)) {
    throw Error(where + ": driver granted " + std::to_string(request.count) + " MMAP buffers for " +
                std::to_string(options_.buffer_count) + " requested; need [" + std::to_string(kMinStreamingBuffers) +
                ", " + std::to_string(kMaxStreamingBuffers) + "]");
  }
  format_.buffer_count = static_cast<int>(request.count);
  for (int i = 0; i < format_.buffer_count; ++i) {
    v4l2_buffer buffer = mmapBuffer(i);
    if (io_.ioctl(fd_, VIDIOC_QUERYBUF, &buffer) < 0) {
      throw DeviceError(where + ": VIDIOC_QUERYBUF(" + std::to_string(i) + ") failed", errno);
    }
    if (buffer.length < format_.size_image) {
      throw Error(where + ": buffer " + std::to_string(i) + " holds " + std::to_string(buffer.length) +
                  " bytes, one frame needs " + std::to_string(format_.size_image));
    }
    void* mapping =
        io_.mmap(nullptr, buffer.length, PROT_READ | PROT_WRITE, MAP_SHARED, fd_, static_cast<off_t>(buffer.m.offset));
    if (mapping == MAP_FAILED) {
      throw DeviceError(where + ": mmap of buffer " + std::to_string(i) + " (" + std::to_string(buffer.length) +
                            " bytes at offset " + std::to_string(buffer.m.offset) + ") failed",
                        errno);
    }
    slots_[static_cast<std::size_t>(i)] =
        BufferSlot{static_cast<std::uint8_t*>(mapping), buffer.length, SlotState::kWithCaller};
  }
}

void V4l2Stream::queueAllAndStreamOn() {
  const std::string where = options_.label + " " + options_.node_path;
  for (int i = 0; i < format_.buffer_count; ++i) {
    v4l2_buffer buffer = mmapBuffer(i);
    if (io_.ioctl(fd_, VIDIOC_QBUF, &buffer) < 0) {
      throw DeviceError(where + ": VIDIOC_QBUF(" + std::to_string(i) + ") failed", errno);
    }
    slots_[static_cast<std::size_t>(i)].state = SlotState::kQueued;
    ++queued_count_;
  }
  int type = static_cast<int>(kCaptureType);
  if (io_.ioctl(fd_, VIDIOC_STREAMON, &type) < 0) throw DeviceError(where + ": VIDIOC_STREAMON failed", errno);
  stream_on_ = true;
}

// ---- stop ----

void V4l2Stream::stop() noexcept {
  if (fd_ < 0) return;
  ++generation_;
  // Errors are ignored on purpose: after an unplug every ioctl fails with ENODEV, yet the mappings must still
  // go and the descriptor must still be closed.
  if (stream_on_) {
    int type = static_cast<int>(kCaptureType);
    io_.ioctl(fd_, VIDIOC_STREAMOFF, &type);
    stream_on_ = false;
  }
  for (BufferSlot& slot : slots_) {
    if (slot.data != nullptr) io_.munmap(slot.data, slot.length);
    slot = BufferSlot{};
  }
  queued_count_ = 0;
  if (buffers_requested_) {
    v4l2_requestbuffers release{};
    release.count = 0;
    release.type = kCaptureType;
    release.memory = V4L2_MEMORY_MMAP;
    io_.ioctl(fd_, VIDIOC_REQBUFS, &release);
    buffers_requested_ = false;
  }
  io_.close(fd_);
  fd_ = -1;
  format_.buffer_count = 0;
  state_ = State::kStopped;
}

// ---- streaming ----

V4l2Stream::Dequeue V4l2Stream::dequeue(v4l2_buffer& buffer) {
  buffer = mmapBuffer(0);
  if (io_.ioctl(fd_, VIDIOC_DQBUF, &buffer) == 0) return Dequeue::kGot;
  return errno == EAGAIN ? Dequeue::kNothingReady : Dequeue::kFailed;
}

NextResult V4l2Stream::next(std::int64_t timeout_ns) {
  if (state_ == State::kUnplugged) return NextResult{NextStatus::kUnplugged, {}};
  if (state_ != State::kStreaming) {
    ++counts_.errors;
    problem_.set("%s %s: next() before start()", options_.label.c_str(), options_.node_path.c_str());
    return NextResult{NextStatus::kError, {}};
  }
  if (queued_count_ == 0) {
    // Without a queued buffer the driver drops every frame and poll would only time out.
    ++counts_.errors;
    problem_.set("%s %s: all %d buffers are held by the caller; release frames before asking for more",
                 options_.label.c_str(), options_.node_path.c_str(), format_.buffer_count);
    return NextResult{NextStatus::kError, {}};
  }
  v4l2_buffer buffer{};
  Dequeue result = dequeue(buffer);
  if (result == Dequeue::kNothingReady) {
    pollfd descriptor{fd_, POLLIN, 0};
    const int ready = io_.poll(&descriptor, 1, pollTimeoutMs(timeout_ns));
    if (ready < 0) return fail("poll", errno);
    if (ready == 0) {
      ++counts_.timeouts;
      return NextResult{NextStatus::kTimeout, {}};
    }
    if ((descriptor.revents & POLLNVAL) != 0) return fail("poll (POLLNVAL: descriptor not open)", EBADF);
    // POLLIN: a buffer is done. POLLERR: not streaming, queue in error, or device gone; DQBUF says which.
    result = dequeue(buffer);
    if (result == Dequeue::kNothingReady) {
      if ((descriptor.revents & POLLERR) != 0) return fail("poll (POLLERR) then VIDIOC_DQBUF", EAGAIN);
      ++counts_.timeouts;  // woken without a buffer: nothing to deliver within this call
      return NextResult{NextStatus::kTimeout, {}};
    }
  }
  if (result == Dequeue::kFailed) return fail("VIDIOC_DQBUF", errno);
  return handleBuffer(buffer);
}

NextResult V4l2Stream::handleBuffer(const v4l2_buffer& buffer) {
  const char* label = options_.label.c_str();
  const int index = static_cast<int>(buffer.index);
  if (index < 0 || index >= format_.buffer_count || slots_[buffer.index].state != SlotState::kQueued) {
    ++counts_.errors;
    problem_.set("%s: VIDIOC_DQBUF returned buffer index %u, which is not one of the %d queued buffers", label,
                 buffer.index, format_.buffer_count);
    return NextResult{NextStatus::kError, {}};
  }
  BufferSlot& slot = slots_[buffer.index];
  slot.state = SlotState::kWithCaller;
  --queued_count_;

  sequence_gaps_.observe(buffer.sequence);  // a gap is counted there; it is no reason to refuse this frame

  if ((buffer.flags & V4L2_BUF_FLAG_ERROR) != 0) {
    problem_.set("%s: buffer %d (sequence %u) flagged V4L2_BUF_FLAG_ERROR: corrupt or incomplete transfer", label,
                 index, buffer.sequence);
    ++counts_.error_flagged_buffers;
    return reject(index);
  }
  if (buffer.bytesused < format_.size_image || buffer.bytesused > slot.length) {
    problem_.set("%s: buffer %d (sequence %u) bytesused %u, expected %u (buffer length %zu)", label, index,
                 buffer.sequence, buffer.bytesused, format_.size_image, slot.length);
    ++counts_.short_buffers;
    return reject(index);
  }
  const std::int64_t t_stamp_ns = timevalToNs(buffer.timestamp);
  ProblemText reason;
  const auto t_mid_ns = mid_exposure_clock_.midExposureNs(buffer.flags, t_stamp_ns, timing_, reason);
  if (!t_mid_ns) {
    problem_.set("%s: buffer %d (sequence %u): %s", label, index, buffer.sequence, reason.c_str());
    return reject(index);  // MidExposureClock counts its own refusals
  }

  FrameView view;
  view.bytes = std::span<const std::uint8_t>(slot.data, buffer.bytesused);
  view.bytes_per_line = format_.bytes_per_line;
  view.sequence = buffer.sequence;
  view.t_stamp_ns = t_stamp_ns;
  view.t_mid_exposure_ns = *t_mid_ns;
  view.flags = buffer.flags;
  view.buffer_index = index;
  ++counts_.frames;
  return NextResult{NextStatus::kFrame, BorrowedFrame(this, view, generation_)};
}

NextResult V4l2Stream::reject(int index) {
  if (!requeue(index)) {
    return NextResult{state_ == State::kUnplugged ? NextStatus::kUnplugged : NextStatus::kError, {}};
  }
  return NextResult{NextStatus::kRejected, {}};
}

NextResult V4l2Stream::fail(const char* call, int error_number) {
  if (isDeviceGoneErrno(error_number)) {
    if (state_ != State::kUnplugged) ++counts_.unplugs;
    state_ = State::kUnplugged;
    problem_.set("%s %s: device gone (%s: %s); stop() and wait for it to come back", options_.label.c_str(),
                 options_.node_path.c_str(), call, errnoName(error_number));
    return NextResult{NextStatus::kUnplugged, {}};
  }
  ++counts_.errors;
  problem_.set("%s %s: %s failed: %s", options_.label.c_str(), options_.node_path.c_str(), call,
               errnoName(error_number));
  return NextResult{NextStatus::kError, {}};
}

bool V4l2Stream::requeue(int index) {
  BufferSlot& slot = slots_[static_cast<std::size_t>(index)];
  v4l2_buffer buffer = mmapBuffer(index);
  if (io_.ioctl(fd_, VIDIOC_QBUF, &buffer) < 0) {
    const int error_number = errno;
    slot.state = SlotState::kUnused;  // the driver did not take it back; never queue it twice
    if (isDeviceGoneErrno(error_number)) {
      fail("VIDIOC_QBUF", error_number);
    } else {
      ++counts_.errors;
      problem_.set("%s %s: VIDIOC_QBUF(%d) failed: %s; the stream has one buffer fewer", options_.label.c_str(),
                   options_.node_path.c_str(), index, errnoName(error_number));
    }
    return false;
  }
  slot.state = SlotState::kQueued;
  ++queued_count_;
  return true;
}

void V4l2Stream::releaseFrame(int index, std::uint64_t generation) noexcept {
  // A frame borrowed before stop() (or before an unplug) has nothing to give back.
  if (generation != generation_ || state_ != State::kStreaming) return;
  if (index < 0 || index >= format_.buffer_count) return;
  if (slots_[static_cast<std::size_t>(index)].state != SlotState::kWithCaller) return;
  requeue(index);
}

V4l2StreamStats V4l2Stream::stats() const {
  V4l2StreamStats stats = counts_;
  stats.sequence_gap_frames = sequence_gaps_.missingFrames();
  stats.sequence_regressions = sequence_gaps_.regressions();
  stats.embedded_gap_frames = embedded_gaps_.missingFrames();
  stats.embedded_counter_regressions = embedded_gaps_.regressions();
  stats.refused_timestamps = mid_exposure_clock_.refusals();
  return stats;
}

}  // namespace vifusion::v4l2
