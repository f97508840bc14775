#include "node_instance.hpp"

#include <linux/usb/video.h>
#include <linux/uvcvideo.h>
#include <poll.h>
#include <sys/mman.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "vifusion/core/time.hpp"
#include "vifusion/v4l2/fourcc.hpp"
#include "vifusion/v4l2_scripted/scripted_v4l2_device.hpp"

namespace vifusion::v4l2_scripted {
namespace {

constexpr std::uint32_t kCaptureType = V4L2_BUF_TYPE_VIDEO_CAPTURE;
/// MMAP offsets are page multiples, as vb2 hands them out.
constexpr std::uint32_t kPageBytes = 4096;
/// What QUERYCAP reports as the driver version (KERNEL_VERSION(6, 1, 0), Debian 12's kernel).
constexpr std::uint32_t kDriverVersion = (6u << 16) | (1u << 8);

std::uint32_t roundUpToPage(std::uint32_t bytes) { return (bytes + kPageBytes - 1) / kPageBytes * kPageBytes; }

template <std::size_t N>
void copyText(std::uint8_t (&destination)[N], const std::string& text) {
  std::memset(destination, 0, N);
  std::memcpy(destination, text.data(), text.size() < N - 1 ? text.size() : N - 1);
}

timeval toTimeval(std::int64_t t_ns) {
  // V4L2 reports whole microseconds; floor, so that a stamp never moves later than the scripted time.
  std::int64_t t_us = t_ns / kNsPerMicrosecond;
  if (t_ns < 0 && t_ns % kNsPerMicrosecond != 0) --t_us;
  constexpr std::int64_t kUsPerSecond = kNsPerSecond / kNsPerMicrosecond;
  std::int64_t seconds = t_us / kUsPerSecond;
  std::int64_t micros = t_us % kUsPerSecond;
  if (micros < 0) {
    micros += kUsPerSecond;
    --seconds;
  }
  timeval time{};
  time.tv_sec = static_cast<decltype(time.tv_sec)>(seconds);
  time.tv_usec = static_cast<decltype(time.tv_usec)>(micros);
  return time;
}

std::uint32_t bytesPerLine(const ScriptedFormat& format) {
  if (format.bytes_per_line != 0) return format.bytes_per_line;
  return static_cast<std::uint32_t>(format.width_px * v4l2::bytesPerPixel(format.fourcc));
}

int nearestRate(const std::vector<int>& rates, int wanted) {
  int best = rates.front();
  for (int rate : rates) {
    if (std::abs(rate - wanted) < std::abs(best - wanted)) best = rate;
  }
  return best;
}

}  // namespace

NodeInstance::NodeInstance(const ScriptedNodeConfig& config, ScriptedV4l2Device& device)
    : config_(config), device_(device), controls_(config.controls) {
  const ScriptedFormat& initial = config.formats.front();
  v4l2_format format{};
  format.type = kCaptureType;
  format.fmt.pix.pixelformat = initial.fourcc;
  format.fmt.pix.width = static_cast<std::uint32_t>(initial.width_px);
  format.fmt.pix.height = static_cast<std::uint32_t>(initial.height_px);
  setFormat(format, true);
}

// ---- ioctl dispatch ----

int NodeInstance::ioctl(int fd, int file_flags, unsigned long request, void* argument) {
  switch (request) {
    case VIDIOC_QUERYCAP:
      return queryCapability(*static_cast<v4l2_capability*>(argument));
    case VIDIOC_G_FMT:
      return getFormat(*static_cast<v4l2_format*>(argument));
    case VIDIOC_S_FMT:
      return setFormat(*static_cast<v4l2_format*>(argument), true);
    case VIDIOC_TRY_FMT:
      return setFormat(*static_cast<v4l2_format*>(argument), false);
    case VIDIOC_S_PARM:
      return setParameters(*static_cast<v4l2_streamparm*>(argument));
    case VIDIOC_G_PARM:
      return getParameters(*static_cast<v4l2_streamparm*>(argument));
    case VIDIOC_REQBUFS:
      return requestBuffers(fd, *static_cast<v4l2_requestbuffers*>(argument));
    case VIDIOC_QUERYBUF:
      return queryBuffer(*static_cast<v4l2_buffer*>(argument));
    case VIDIOC_QBUF:
      return queueBuffer(fd, *static_cast<v4l2_buffer*>(argument));
    case VIDIOC_DQBUF:
      return dequeueBuffer(fd, file_flags, *static_cast<v4l2_buffer*>(argument));
    case VIDIOC_STREAMON:
      return streamOn(fd, static_cast<const int*>(argument));
    case VIDIOC_STREAMOFF:
      return streamOff(fd, static_cast<const int*>(argument));
    case UVCIOC_CTRL_QUERY:
      return controlQuery(argument);
    default:
      return ENOTTY;  // not a request this node knows; clients may probe, so no violation
  }
}

int NodeInstance::queryCapability(v4l2_capability& capability) const {
  capability = v4l2_capability{};
  copyText(capability.driver, config_.driver);
  copyText(capability.card, config_.card);
  copyText(capability.bus_info, config_.bus_info);
  capability.version = kDriverVersion;
  capability.capabilities = config_.device_caps | V4L2_CAP_DEVICE_CAPS;
  capability.device_caps = config_.device_caps;
  return 0;
}

// ---- format and rate ----

const ScriptedFormat* NodeInstance::findFormat(std::uint32_t fourcc, int width_px, int height_px) const {
  // Like uvcvideo: an unknown fourcc becomes the default format's, then the nearest offered size wins.
  bool known = false;
  for (const ScriptedFormat& format : config_.formats) known = known || format.fourcc == fourcc;
  const std::uint32_t chosen_fourcc = known ? fourcc : config_.formats.front().fourcc;
  const ScriptedFormat* best = nullptr;
  long best_distance = 0;
  for (const ScriptedFormat& format : config_.formats) {
    if (format.fourcc != chosen_fourcc) continue;
    const long distance = std::labs(static_cast<long>(format.width_px) - width_px) +
                          std::labs(static_cast<long>(format.height_px) - height_px);
    if (best == nullptr || distance < best_distance) {
      best = &format;
      best_distance = distance;
    }
  }
  return best;
}

int NodeInstance::setFormat(v4l2_format& format, bool apply) {
  if (format.type != kCaptureType) {
    return device_.violation(EINVAL, "%s S_FMT/TRY_FMT: buffer type %u, only VIDEO_CAPTURE", config_.path.c_str(),
                             format.type);
  }
  if (apply && !buffers_.empty()) {
    return device_.violation(EBUSY, "%s S_FMT while %zu buffers are allocated", config_.path.c_str(), buffers_.size());
  }
  const ScriptedFormat* chosen = findFormat(format.fmt.pix.pixelformat, static_cast<int>(format.fmt.pix.width),
                                            static_cast<int>(format.fmt.pix.height));
  v4l2_pix_format& pix = format.fmt.pix;
  pix = v4l2_pix_format{};
  pix.width = static_cast<std::uint32_t>(chosen->width_px);
  pix.height = static_cast<std::uint32_t>(chosen->height_px);
  pix.pixelformat = chosen->fourcc;
  pix.field = V4L2_FIELD_NONE;
  pix.bytesperline = bytesPerLine(*chosen);
  pix.sizeimage = pix.bytesperline * pix.height;
  pix.colorspace = V4L2_COLORSPACE_SRGB;
  if (apply) {
    format_ = pix;
    format_rates_ = chosen->fps;
    fps_ = nearestRate(format_rates_, fps_ > 0 ? fps_ : format_rates_.front());
  }
  return 0;
}

int NodeInstance::getFormat(v4l2_format& format) const {
  if (format.type != kCaptureType) {
    return device_.violation(EINVAL, "%s G_FMT: buffer type %u, only VIDEO_CAPTURE", config_.path.c_str(), format.type);
  }
  format.fmt.pix = format_;
  return 0;
}

int NodeInstance::setParameters(v4l2_streamparm& parameters) {
  if (parameters.type != kCaptureType) {
    return device_.violation(EINVAL, "%s S_PARM: buffer type %u, only VIDEO_CAPTURE", config_.path.c_str(),
                             parameters.type);
  }
  if (streaming_) return device_.violation(EBUSY, "%s S_PARM while streaming", config_.path.c_str());
  const v4l2_fract asked = parameters.parm.capture.timeperframe;
  if (asked.numerator != 0 && asked.denominator != 0) {
    fps_ = nearestRate(format_rates_, static_cast<int>(asked.denominator / asked.numerator));
  }
  return getParameters(parameters);
}

int NodeInstance::getParameters(v4l2_streamparm& parameters) const {
  if (parameters.type != kCaptureType) {
    return device_.violation(EINVAL, "%s G_PARM: buffer type %u, only VIDEO_CAPTURE", config_.path.c_str(),
                             parameters.type);
  }
  parameters.parm.capture = v4l2_captureparm{};
  parameters.parm.capture.capability = V4L2_CAP_TIMEPERFRAME;
  parameters.parm.capture.timeperframe.numerator = 1;
  parameters.parm.capture.timeperframe.denominator = static_cast<std::uint32_t>(fps_);
  return 0;
}

// ---- buffers ----

int NodeInstance::checkOwner(int fd, const char* call) const {
  // As vb2: only another descriptor's queue is busy; without an owner the call fails on its own rules.
  if (queue_owner_fd_ >= 0 && queue_owner_fd_ != fd) {
    return device_.violation(EBUSY, "%s %s from fd %d, but the queue belongs to fd %d", config_.path.c_str(), call, fd,
                             queue_owner_fd_);
  }
  return 0;
}

int NodeInstance::checkBufferRequest(const v4l2_buffer& buffer, const char* call) const {
  if (buffer.type != kCaptureType || buffer.memory != V4L2_MEMORY_MMAP) {
    return device_.violation(EINVAL, "%s %s: type %u memory %u, expected VIDEO_CAPTURE and MMAP", config_.path.c_str(),
                             call, buffer.type, buffer.memory);
  }
  if (buffer.index >= buffers_.size()) {
    return device_.violation(EINVAL, "%s %s(%u): only %zu buffers exist", config_.path.c_str(), call, buffer.index,
                             buffers_.size());
  }
  return 0;
}

int NodeInstance::requestBuffers(int fd, v4l2_requestbuffers& request) {
  const char* path = config_.path.c_str();
  if (request.type != kCaptureType || request.memory != V4L2_MEMORY_MMAP) {
    return device_.violation(EINVAL, "%s REQBUFS: type %u memory %u, only VIDEO_CAPTURE and MMAP", path, request.type,
                             request.memory);
  }
  if (queue_owner_fd_ >= 0 && queue_owner_fd_ != fd) {
    return device_.violation(EBUSY, "%s REQBUFS from fd %d, but fd %d owns the queue", path, fd, queue_owner_fd_);
  }
  if (streaming_) return device_.violation(EBUSY, "%s REQBUFS while streaming", path);
  if (liveMappings() > 0) {
    return device_.violation(EBUSY, "%s REQBUFS(%u) while %d buffers are still mapped", path, request.count,
                             liveMappings());
  }
  freeBuffers();
  if (request.count == 0) {
    queue_owner_fd_ = -1;
    return 0;
  }
  const int count =
      static_cast<int>(request.count) < config_.max_buffers ? static_cast<int>(request.count) : config_.max_buffers;
  const std::uint32_t stride = roundUpToPage(format_.sizeimage);
  buffers_.resize(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    Buffer& buffer = buffers_[static_cast<std::size_t>(i)];
    buffer.storage = std::make_unique<Storage>();
    buffer.storage->bytes.assign(stride, 0);
    buffer.offset = stride * static_cast<std::uint32_t>(i);
    buffer.owner = Owner::kClient;
  }
  queued_.reset(count);
  done_.reset(count);
  queue_owner_fd_ = fd;
  request.count = static_cast<std::uint32_t>(count);
  request.capabilities = V4L2_BUF_CAP_SUPPORTS_MMAP;
  return 0;
}

void NodeInstance::describe(v4l2_buffer& buffer, int index) const {
  const Buffer& slot = buffers_[static_cast<std::size_t>(index)];
  buffer.index = static_cast<std::uint32_t>(index);
  buffer.type = kCaptureType;
  buffer.memory = V4L2_MEMORY_MMAP;
  buffer.length = static_cast<std::uint32_t>(slot.storage->bytes.size());
  buffer.m.offset = slot.offset;
  buffer.bytesused = slot.bytes_used;
  buffer.field = V4L2_FIELD_NONE;
  buffer.sequence = slot.sequence;
  buffer.timestamp = toTimeval(slot.t_stamp_ns);
  buffer.flags = slot.flags;
  if (slot.owner == Owner::kQueued) buffer.flags |= V4L2_BUF_FLAG_QUEUED;
  if (slot.owner == Owner::kDone) buffer.flags |= V4L2_BUF_FLAG_DONE;
  if (slot.storage->maps > 0) buffer.flags |= V4L2_BUF_FLAG_MAPPED;
}

int NodeInstance::queryBuffer(v4l2_buffer& buffer) const {
  if (const int error = checkBufferRequest(buffer, "QUERYBUF")) return error;
  describe(buffer, static_cast<int>(buffer.index));
  return 0;
}

int NodeInstance::queueBuffer(int fd, v4l2_buffer& buffer) {
  if (const int error = checkOwner(fd, "QBUF")) return error;
  if (const int error = checkBufferRequest(buffer, "QBUF")) return error;
  Buffer& slot = buffers_[buffer.index];
  if (slot.owner != Owner::kClient) {
    return device_.violation(EINVAL, "%s QBUF(%u): the buffer is %s, not held by the client", config_.path.c_str(),
                             buffer.index, slot.owner == Owner::kQueued ? "queued already" : "done, not dequeued");
  }
  slot.owner = Owner::kQueued;
  slot.flags = 0;
  queued_.push(static_cast<int>(buffer.index));
  ++stats_.queued;
  describe(buffer, static_cast<int>(buffer.index));
  return 0;
}

int NodeInstance::dequeueBuffer(int fd, int file_flags, v4l2_buffer& buffer) {
  (void)file_flags;  // blocking is the device's job: it advances the clock while this returns EAGAIN
  if (const int error = checkOwner(fd, "DQBUF")) return error;
  if (buffer.type != kCaptureType || buffer.memory != V4L2_MEMORY_MMAP) {
    return device_.violation(EINVAL, "%s DQBUF: type %u memory %u, expected VIDEO_CAPTURE and MMAP",
                             config_.path.c_str(), buffer.type, buffer.memory);
  }
  if (!streaming_) return device_.violation(EINVAL, "%s DQBUF while not streaming", config_.path.c_str());
  if (done_.empty()) return EAGAIN;
  const int index = done_.pop();
  buffers_[static_cast<std::size_t>(index)].owner = Owner::kClient;
  ++stats_.dequeued;
  describe(buffer, index);
  return 0;
}

int NodeInstance::streamOn(int fd, const int* type) {
  if (const int error = checkOwner(fd, "STREAMON")) return error;
  if (*type != static_cast<int>(kCaptureType)) {
    return device_.violation(EINVAL, "%s STREAMON: type %d, only VIDEO_CAPTURE", config_.path.c_str(), *type);
  }
  if (buffers_.empty()) return device_.violation(EINVAL, "%s STREAMON without buffers", config_.path.c_str());
  if (streaming_) return 0;
  streaming_ = true;
  next_sequence_ = 0;
  // The first frame served is the first to complete after now.
  const std::int64_t now_ns = device_.clock().nowNs();
  const std::int64_t first_ns = config_.schedule.first_arrival_ns;
  next_frame_index_ = now_ns < first_ns ? 0 : (now_ns - first_ns) / periodNs() + 1;
  return 0;
}

int NodeInstance::streamOff(int fd, const int* type) {
  if (const int error = checkOwner(fd, "STREAMOFF")) return error;
  if (*type != static_cast<int>(kCaptureType)) {
    return device_.violation(EINVAL, "%s STREAMOFF: type %d, only VIDEO_CAPTURE", config_.path.c_str(), *type);
  }
  stopStreaming();
  return 0;
}

void NodeInstance::stopStreaming() {
  streaming_ = false;
  for (Buffer& buffer : buffers_) buffer.owner = Owner::kClient;
  queued_.clear();
  done_.clear();
}

void NodeInstance::freeBuffers() {
  for (Buffer& buffer : buffers_) {
    if (buffer.storage && buffer.storage->maps > 0) orphans_.push_back(std::move(buffer.storage));
  }
  buffers_.clear();
  queued_.clear();
  done_.clear();
}

// ---- controls ----

ScriptedControl* NodeInstance::findControl(std::uint8_t unit, std::uint8_t selector) {
  for (ScriptedControl& entry : controls_) {
    if (entry.unit == unit && entry.selector == selector) return &entry;
  }
  return nullptr;
}

const ScriptedControl* NodeInstance::control(std::uint8_t unit, std::uint8_t selector) const {
  return const_cast<NodeInstance*>(this)->findControl(unit, selector);
}

int NodeInstance::controlQuery(void* argument) {
  auto& query = *static_cast<uvc_xu_control_query*>(argument);
  ScriptedControl* entry = findControl(query.unit, query.selector);
  if (entry == nullptr) return ENOENT;
  if (query.size != entry->value.size()) return ENOBUFS;
  if (query.data == nullptr) return device_.violation(EFAULT, "%s UVCIOC_CTRL_QUERY: null data", config_.path.c_str());
  switch (query.query) {
    case UVC_GET_CUR:
      std::memcpy(query.data, entry->value.data(), entry->value.size());
      return 0;
    case UVC_SET_CUR:
      if (!entry->writable) return EIO;
      std::memcpy(entry->value.data(), query.data, entry->value.size());
      return 0;
    default:
      return EINVAL;
  }
}

// ---- memory ----

int NodeInstance::mmap(std::size_t length, int protection, int flags, off_t offset, void** mapping) {
  const char* path = config_.path.c_str();
  if ((flags & MAP_SHARED) == 0 || (protection & PROT_READ) == 0) {
    return device_.violation(EINVAL, "%s mmap: flags 0x%x protection 0x%x, need MAP_SHARED and PROT_READ", path, flags,
                             protection);
  }
  for (Buffer& buffer : buffers_) {
    if (static_cast<off_t>(buffer.offset) != offset) continue;
    if (length == 0 || length > buffer.storage->bytes.size()) {
      return device_.violation(EINVAL, "%s mmap of %zu bytes at offset %lld: the buffer has %zu", path, length,
                               static_cast<long long>(offset), buffer.storage->bytes.size());
    }
    ++buffer.storage->maps;
    *mapping = buffer.storage->bytes.data();
    return 0;
  }
  return device_.violation(EINVAL, "%s mmap at offset %lld: no buffer there (%zu buffers)", path,
                           static_cast<long long>(offset), buffers_.size());
}

bool NodeInstance::unmap(void* address) {
  for (Buffer& buffer : buffers_) {
    if (buffer.storage->bytes.data() == address && buffer.storage->maps > 0) {
      --buffer.storage->maps;
      return true;
    }
  }
  for (std::size_t i = 0; i < orphans_.size(); ++i) {
    if (orphans_[i]->bytes.data() == address && orphans_[i]->maps > 0) {
      if (--orphans_[i]->maps == 0) orphans_.erase(orphans_.begin() + static_cast<std::ptrdiff_t>(i));
      return true;
    }
  }
  return false;
}

int NodeInstance::liveMappings() const {
  int count = 0;
  for (const Buffer& buffer : buffers_) count += buffer.storage->maps;
  for (const auto& orphan : orphans_) count += orphan->maps;
  return count;
}

void NodeInstance::closeFile(int fd) {
  if (fd != queue_owner_fd_) return;
  stopStreaming();
  freeBuffers();
  queue_owner_fd_ = -1;
}

// ---- time ----

short NodeInstance::pollEvents() const {
  if (!streaming_) return POLLERR;
  return done_.empty() ? 0 : static_cast<short>(POLLIN | POLLRDNORM);
}

std::int64_t NodeInstance::periodNs() const {
  if (config_.schedule.period_ns > 0) return config_.schedule.period_ns;
  return (kNsPerSecond + fps_ / 2) / fps_;
}

std::optional<std::int64_t> NodeInstance::nextArrivalNs() const {
  if (gone_ || !streaming_) return std::nullopt;
  const std::int64_t frame_count = config_.schedule.frame_count;
  if (frame_count >= 0 && next_frame_index_ >= frame_count) return std::nullopt;
  return config_.schedule.first_arrival_ns + next_frame_index_ * periodNs();
}

void NodeInstance::deliverArrival() {
  const std::int64_t index = next_frame_index_;
  const std::int64_t arrival_ns = config_.schedule.first_arrival_ns + index * periodNs();
  ++next_frame_index_;
  ++stats_.arrivals;
  const std::uint32_t sequence = next_sequence_++;
  if (queued_.empty()) {
    ++stats_.dropped_no_buffer;
    return;
  }
  const int buffer_index = queued_.front();
  Buffer& buffer = buffers_[static_cast<std::size_t>(buffer_index)];
  ScriptedFrameRequest request;
  request.frame_index = index;
  request.arrival_ns = arrival_ns;
  request.sequence = sequence;
  request.format = format_;
  request.payload = std::span<std::uint8_t>(buffer.storage->bytes.data(), format_.sizeimage);
  ScriptedFrame frame;
  frame.t_stamp_ns = arrival_ns;
  frame.bytes_used = format_.sizeimage;
  config_.schedule.produce(request, frame);
  if (frame.lost) {
    ++stats_.lost_by_script;
    return;
  }
  queued_.pop();
  buffer.owner = Owner::kDone;
  buffer.sequence = sequence;
  buffer.t_stamp_ns = frame.t_stamp_ns;
  buffer.flags = frame.timestamp_flags | (frame.error ? V4L2_BUF_FLAG_ERROR : 0u);
  buffer.bytes_used = frame.bytes_used;
  done_.push(buffer_index);
  ++stats_.filled;
}

ScriptedNodeStats NodeInstance::stats() const {
  ScriptedNodeStats stats = stats_;
  stats.streaming = streaming_;
  stats.buffers = static_cast<int>(buffers_.size());
  stats.mapped_buffers = liveMappings();
  return stats;
}

}  // namespace vifusion::v4l2_scripted
