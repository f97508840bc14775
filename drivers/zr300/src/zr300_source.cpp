#include "vifusion/zr300/zr300_source.hpp"

#include <fcntl.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdarg>
#include <cstdio>

#include "vifusion/core/error.hpp"
#include "vifusion/core/thread_cpu_time.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/v4l2/device_error.hpp"
#include "vifusion/v4l2/ds_metadata.hpp"
#include "vifusion/v4l2/uvc_xu.hpp"
#include "vifusion/v4l2/yuyv.hpp"
#include "vifusion/v4l2/z16.hpp"

namespace vifusion::zr300 {
namespace {

using discovery::Zr300Stream;

/// How often nextFrame() and the camera thread look again while they wait for the other side [ns].
constexpr std::int64_t kWaitStepNs = 500'000;
/// A colour frame may complete up to this many frame periods after its depth frame.
constexpr std::int64_t kColourWaitPeriods = 2;
/// The DS4 depth unit as metres: divided rather than multiplied by 1e-6, so that 200 µm gives exactly the
/// double nearest 1/5000 m (the recorded datasets' unit), and a replay compares bit for bit.
constexpr double kMicrometresPerMetre = 1e6;

void sleepNs(std::int64_t ns) { std::this_thread::sleep_for(std::chrono::nanoseconds(ns)); }

v4l2::V4l2StreamOptions streamOptions(const char* label, const std::string& node, std::uint32_t fourcc, int width,
                                      int height, const Zr300Options& options) {
  v4l2::V4l2StreamOptions stream;
  stream.label = label;
  stream.node_path = node;
  stream.fourcc = fourcc;
  stream.width_px = width;
  stream.height_px = height;
  stream.fps = options.preset.fps;
  stream.buffer_count = options.buffer_count;
  return stream;
}

/// Signed distance from counter `a` to `b` modulo 2³² (positive: b is after a).
std::int32_t counterDistance(std::uint32_t a, std::uint32_t b) { return static_cast<std::int32_t>(b - a); }

}  // namespace

Zr300Source::Zr300Source(std::unique_ptr<Zr300Backend> backend, const discovery::Zr300SourceSpec& spec,
                         const RigCalibration& calibration, const Zr300Options& options)
    : backend_(std::move(backend)),
      spec_(spec),
      options_((options.validate(), options)),
      calibration_(calibration),
      frames_(options.frame_ring_capacity) {
  if (!backend_) throw Error("Zr300Source: backend is null");
  if (calibration_.camera.width != options_.preset.width_px ||
      calibration_.camera.height != options_.preset.height_px) {
    throw Error("the calibration is for " + std::to_string(calibration_.camera.width) + "x" +
                std::to_string(calibration_.camera.height) + " images, but the camera is asked to stream " +
                std::to_string(options_.preset.width_px) + "x" + std::to_string(options_.preset.height_px));
  }
  // Depth comes from the IR stereo pair, centimetres from the colour imager: without its intrinsics and
  // T_C_D every colour pixel would be paired with the depth of a point beside it.
  if (!calibration_.depth_camera) {
    throw Error(
        "the calibration has no depth camera (cam1 with T_cn_cnm1): the ZR300 measures depth with its IR "
        "pair, not with the colour camera, and its depth must be registered to colour");
  }
  if (calibration_.depth_camera->camera.width != options_.preset.width_px ||
      calibration_.depth_camera->camera.height != options_.preset.height_px) {
    throw Error(
        "the calibration's depth camera (cam1) is for " + std::to_string(calibration_.depth_camera->camera.width) +
        "x" + std::to_string(calibration_.depth_camera->camera.height) + " images, but the camera is asked to stream " +
        std::to_string(options_.preset.width_px) + "x" + std::to_string(options_.preset.height_px));
  }
  discovery::CameraCheckOptions check;
  check.require_adapter = options_.imu;
  camera_ = backend_->findCamera(spec_, check);
  const int width = options_.preset.width_px;
  const int height = options_.preset.height_px;
  pending_.depth.resize(width, height);
  pending_.rgb.resize(width, height);
  openDevices();
  calibration_.depth_scale_m = static_cast<double>(depth_units_um_) / kMicrometresPerMetre;
  if (motion_) {
    LiveImuFeedOptions feed = options_.imu_feed;
    feed.time_shift_cam_imu_ns = calibration_.time_shift_cam_imu_ns;
    imu_feed_.emplace(motion_->imuRing(), feed);
  }
  backend_->follow(camera_);
  updateStats([](Zr300Stats& s) { s.camera_present = true; });
  thread_ = std::thread([this] { cameraLoop(); });
}

Zr300Source::~Zr300Source() {
  requestStop();
  if (thread_.joinable()) thread_.join();
}

void Zr300Source::openDevices() {
  v4l2::DeviceIo& io = backend_->deviceIo();
  try {
    const std::string& infrared = camera_.stream(Zr300Stream::kInfrared).devnode;
    infrared_fd_ = io.open(infrared.c_str(), O_RDWR | O_NONBLOCK);
    if (infrared_fd_ < 0) throw v4l2::DeviceError(infrared + ": open for the DS4 controls", errno);
    v4l2::ds4::setStreamIntent(io, infrared_fd_, v4l2::ds4::kIntentDepth | v4l2::ds4::kIntentColour);
    if (options_.depth_units_um > 0) v4l2::ds4::setDepthUnitsUm(io, infrared_fd_, options_.depth_units_um);
    const std::uint32_t units = v4l2::ds4::depthUnitsUm(io, infrared_fd_);
    if (units == 0) throw Error(infrared + ": the camera reports a depth unit of 0 µm");
    if (depth_units_um_ != 0 && units != depth_units_um_) {
      throw Error(infrared + ": the depth unit changed from " + std::to_string(depth_units_um_) + " to " +
                  std::to_string(units) + " µm across a re-open");
    }
    depth_units_um_ = units;
    v4l2::ds4::setEmitterEnabled(io, infrared_fd_, options_.emitter);

    depth_.emplace(io, streamOptions("depth", camera_.stream(Zr300Stream::kDepth).devnode, v4l2::kFourccZ16,
                                     options_.depthNodeWidthPx(), options_.depthNodeHeightPx(), options_));
    colour_.emplace(io, streamOptions("colour", camera_.stream(Zr300Stream::kColour).devnode, v4l2::kFourccYuyv,
                                      options_.preset.width_px, options_.preset.height_px, options_));
    depth_->start();
    colour_->start();
    if (options_.imu) {
      auto link = backend_->motionLink(camera_, options_.motion.transfers_in_flight);
      if (motion_) {
        motion_->replaceLink(std::move(link));
      } else {
        motion_ = std::make_unique<usb_imu::MotionModule>(std::move(link), options_.motion);
      }
      if (!motion_->start()) throw Error("motion module: the adapter board went away while starting");
    }
  } catch (...) {
    closeDevices();
    throw;
  }
  events_.clear();
}

void Zr300Source::closeDevices() noexcept {
  held_colour_.release();
  depth_.reset();
  colour_.reset();
  if (motion_) motion_->stop();
  if (infrared_fd_ >= 0) backend_->deviceIo().close(infrared_fd_);
  infrared_fd_ = -1;
}

void Zr300Source::cameraLoop() {
  bool streaming = true;
  std::int64_t backoff_ns = options_.reopen_backoff_min_ns;
  while (!stop_.load(std::memory_order_acquire)) {
    if (!streaming) {
      streaming = reopen(backoff_ns);
      continue;
    }
    if (assembleFrame() == Step::kDeviceGone) {
      closeDevices();
      streaming = false;
      updateStats([](Zr300Stats& s) {
        s.camera_present = false;
        ++s.unplugs;
      });
    }
  }
  closeDevices();
}

bool Zr300Source::reopen(std::int64_t& backoff_ns) {
  backend_->waitForHotplug(backoff_ns);
  if (stop_.load(std::memory_order_acquire)) return false;
  try {
    discovery::CameraCheckOptions check;
    check.require_adapter = options_.imu;
    camera_ = backend_->findCamera(spec_, check);
    openDevices();
    backend_->follow(camera_);
  } catch (const std::exception& error) {
    noteProblem("camera absent: %s", error.what());
    backoff_ns = std::min(2 * backoff_ns, options_.reopen_backoff_max_ns);
    return false;
  }
  backoff_ns = options_.reopen_backoff_min_ns;
  updateStats([](Zr300Stats& s) {
    s.camera_present = true;
    ++s.reopens;
  });
  return true;
}

bool Zr300Source::motionGone() const {
  return motion_ && options_.imu && motion_->state() == usb_imu::ModuleState::kUnplugged;
}

Zr300Source::Step Zr300Source::assembleFrame() {
  // A full ring: stop dequeuing, so the driver drops frames (counted from sequence gaps) rather than the ring.
  while (frames_.size() == frames_.capacity()) {
    if (stop_.load(std::memory_order_acquire)) return Step::kContinue;
    sleepNs(kWaitStepNs);
  }
  if (motionGone()) return Step::kDeviceGone;
  v4l2::NextResult depth = depth_->next(options_.poll_timeout_ns);
  switch (depth.status) {
    case v4l2::NextStatus::kFrame:
      break;
    case v4l2::NextStatus::kUnplugged:
      noteProblem("%.*s", static_cast<int>(depth_->lastProblem().size()), depth_->lastProblem().data());
      return Step::kDeviceGone;
    case v4l2::NextStatus::kRejected:
    case v4l2::NextStatus::kError:
      noteProblem("%.*s", static_cast<int>(depth_->lastProblem().size()), depth_->lastProblem().data());
      updateStats([](Zr300Stats& s) { ++s.rejected_frames; });
      return Step::kContinue;
    case v4l2::NextStatus::kTimeout:
      return Step::kContinue;
  }
  const v4l2::FrameView& view = depth.frame.view();
  v4l2::ProblemText problem;
  const std::optional<v4l2::Dinghy> dinghy =
      v4l2::readDinghy(view.bytes, view.bytes_per_line, options_.depthNodeHeightPx(), problem);
  const int width = options_.preset.width_px;
  const int inner_width = options_.depthNodeWidthPx();
  const int inner_height = options_.depthNodeHeightPx() - kDepthMetadataRows;
  if (!dinghy || !v4l2::checkDinghy(*dinghy, v4l2::DinghyNode::kDepth, problem) ||
      !v4l2::z16ToDepth(view.bytes, view.bytes_per_line,
                        ImageView<std::uint16_t>(pending_.depth.data() + kDepthPaddingPx * width + kDepthPaddingPx,
                                                 inner_width, inner_height, width),
                        problem)) {
    noteProblem("depth frame refused: %s", problem.c_str());
    updateStats([](Zr300Stats& s) { ++s.rejected_frames; });
    return Step::kContinue;
  }
  const std::uint32_t counter = dinghy->frame_counter;
  const std::int64_t kernel_mid_ns = view.t_mid_exposure_ns;
  depth_->noteEmbeddedFrameCounter(counter);
  depth.frame.release();

  Step step = Step::kContinue;
  if (!takeColour(counter, step)) return step;
  pending_.timing = FrameTiming{counter, kernel_mid_ns, 0, 0, false};
  const std::int64_t t_ns = frameTime(counter, kernel_mid_ns);
  if (next_index_ > 0 && t_ns <= last_t_ns_) {
    noteProblem("frame with DS4 counter %u at t_ns %lld is not after the previous frame at %lld: dropped", counter,
                static_cast<long long>(t_ns), static_cast<long long>(last_t_ns_));
    updateStats([](Zr300Stats& s) { ++s.time_regressions; });
    return Step::kContinue;
  }
  pending_.t_ns = t_ns;
  pending_.index = next_index_++;
  pending_.depth_scale_m = calibration_.depth_scale_m;
  last_t_ns_ = t_ns;
  frames_.tryPush(std::move(pending_));  // cannot fail: only this thread fills, and a slot was free above
  if (pending_.depth.width() != width || pending_.rgb.width() != width) {  // a never-used slot came back
    pending_.depth.resize(width, options_.preset.height_px);
    pending_.rgb.resize(width, options_.preset.height_px);
  }
  const v4l2::V4l2StreamStats depth_stats = depth_->stats();
  const v4l2::V4l2StreamStats colour_stats = colour_->stats();
  updateStats([&](Zr300Stats& s) {
    ++s.frames;
    s.depth_dropped = depth_stats.sequence_gap_frames + depth_stats.embedded_gap_frames;
    s.colour_dropped = colour_stats.sequence_gap_frames;
  });
  return Step::kContinue;
}

bool Zr300Source::takeColour(std::uint32_t counter, Step& step) {
  const std::int64_t wait_ns = kColourWaitPeriods * kNsPerSecond / options_.preset.fps;
  const int width = options_.preset.width_px;
  const int height = options_.preset.height_px;
  while (true) {
    if (!held_colour_) {
      v4l2::NextResult colour = colour_->next(wait_ns);
      if (colour.status == v4l2::NextStatus::kUnplugged) {
        step = Step::kDeviceGone;
        return false;
      }
      if (colour.status != v4l2::NextStatus::kFrame) {
        if (colour.status != v4l2::NextStatus::kTimeout) {
          noteProblem("%.*s", static_cast<int>(colour_->lastProblem().size()), colour_->lastProblem().data());
        }
        updateStats([](Zr300Stats& s) { ++s.unpaired_depth; });
        return false;
      }
      v4l2::ProblemText problem;
      const v4l2::FrameView& view = colour.frame.view();
      const std::optional<std::uint32_t> raw =
          v4l2::readColourFrameNumber(view.bytes, view.bytes_per_line, width, height, problem);
      if (!raw) {
        noteProblem("colour frame refused: %s", problem.c_str());
        updateStats([](Zr300Stats& s) { ++s.rejected_frames; });
        continue;
      }
      held_colour_number_ = v4l2::colourFrameNumber(*raw, options_.preset.fps, options_.preset.fps);
      held_colour_ = std::move(colour.frame);
    }
    const std::int32_t ahead = counterDistance(counter, held_colour_number_);
    if (ahead < 0) {  // an older colour frame whose depth frame was lost
      held_colour_.release();
      updateStats([](Zr300Stats& s) { ++s.unpaired_colour; });
      continue;
    }
    if (ahead > 0) {  // this depth frame's colour frame was lost: keep the colour frame for a later depth frame
      updateStats([](Zr300Stats& s) { ++s.unpaired_depth; });
      return false;
    }
    v4l2::ProblemText problem;
    const v4l2::FrameView& view = held_colour_.view();
    const bool converted = v4l2::yuyvToRgb(view.bytes, view.bytes_per_line, pending_.rgb.view(), problem);
    held_colour_.release();
    if (!converted) {
      noteProblem("colour frame refused: %s", problem.c_str());
      updateStats([](Zr300Stats& s) { ++s.rejected_frames; });
      return false;
    }
    return true;
  }
}

std::int64_t Zr300Source::frameTime(std::uint32_t counter, std::int64_t kernel_mid_ns) {
  if (motion_) {
    // Until the clock mapping is valid (its first min_span_s after a start or re-open) the module publishes
    // no events: look once, do not wait, so the camera thread keeps the frame rate meanwhile.
    const bool events_flow = motion_->stats().clock_state == clock::ClockMapperState::kValid;
    const auto wait_ns = events_flow ? options_.frame_event_wait_ns : 0;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::nanoseconds(wait_ns);
    usb_imu::DepthFrameEvent event;
    while (true) {
      while (motion_->frameEventRing().tryPop(event)) events_.add(event);
      if (const auto found = events_.find(counter, kernel_mid_ns, options_.frame_event_tolerance_ns)) {
        updateStats([](Zr300Stats& s) { ++s.event_timestamps; });
        pending_.timing.device_event_ns = found->t_ns;
        pending_.timing.device_event_clock_ns = found->device_ns;
        pending_.timing.stamped_by_device_event = true;
        return found->t_ns;
      }
      if (std::chrono::steady_clock::now() >= deadline || motionGone()) break;
      sleepNs(kWaitStepNs);
    }
  }
  updateStats([](Zr300Stats& s) { ++s.kernel_timestamps; });
  return kernel_mid_ns;
}

bool Zr300Source::nextFrame(RgbdFrame& frame) {
  while (!stop_.load(std::memory_order_acquire)) {
    if (frames_.tryPop(frame)) return true;
    sleepNs(kWaitStepNs);
  }
  return false;
}

std::int64_t Zr300Source::driverCpuNs() const {
  const std::int64_t camera = thread_.joinable() ? threadCpuTimeNs(const_cast<std::thread&>(thread_)) : 0;
  return camera + (motion_ ? motion_->threadCpuNs() : 0);
}

Zr300Stats Zr300Source::stats() const {
  Zr300Stats copy;
  {
    const std::lock_guard lock(stats_mutex_);
    copy = stats_;
  }
  if (motion_) copy.motion = motion_->stats();
  return copy;
}

std::string Zr300Source::lastProblem() const {
  const std::lock_guard lock(stats_mutex_);
  return std::string(problem_.view());
}

void Zr300Source::noteProblem(const char* format, ...) {
  char text[v4l2::ProblemText::kCapacity + 1];
  va_list arguments;
  va_start(arguments, format);
  std::vsnprintf(text, sizeof(text), format, arguments);
  va_end(arguments);
  const std::lock_guard lock(stats_mutex_);
  problem_.set("%s", text);
}

std::string Zr300Source::describe() const {
  char text[512];
  std::snprintf(
      text, sizeof(text), "%s (live): depth %s Z16 %dx%d and colour %s YUYV %dx%d at %d Hz, depth unit %u um, IMU %s",
      camera_.label().c_str(), camera_.stream(Zr300Stream::kDepth).devnode.c_str(), options_.depthNodeWidthPx(),
      options_.depthNodeHeightPx(), camera_.stream(Zr300Stream::kColour).devnode.c_str(), options_.preset.width_px,
      options_.preset.height_px, options_.preset.fps, depth_units_um_,
      motion_ ? camera_.adapter->usb.devnode.c_str() : "off");
  return text;
}

}  // namespace vifusion::zr300
