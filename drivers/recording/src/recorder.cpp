#include "vifusion/recording/recorder.hpp"

#include <algorithm>
#include <chrono>

#include "vifusion/core/error.hpp"
#include "vifusion/core/thread_cpu_time.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion::recording {
namespace {

constexpr std::size_t kMaxFrameRing = 256;
constexpr std::size_t kMaxSampleRing = std::size_t{1} << 20;
constexpr std::size_t kMaxMotionRing = std::size_t{1} << 16;
constexpr std::int64_t kMaxIdleWaitNs = 100 * kNsPerMillisecond;

void checkRing(std::size_t value, std::size_t max, const char* field) {
  if (value < 1 || value > max) {
    throw Error("recorder option '" + std::string(field) + "' must be in [1, " + std::to_string(max) + "], got " +
                std::to_string(value));
  }
}

/// A frame with images of the calibration's sizes, so ring slots never resize.
RgbdFrame framePrototype(const RigCalibration& calibration) {
  const PinholeCamera& depth = calibration.depth_camera ? calibration.depth_camera->camera : calibration.camera;
  RgbdFrame frame;
  frame.depth.resize(depth.width, depth.height);
  frame.rgb.resize(calibration.camera.width, calibration.camera.height);
  return frame;
}

}  // namespace

void RecorderOptions::validate() const {
  checkRing(frame_ring, kMaxFrameRing, "frame_ring");
  checkRing(imu_ring, kMaxSampleRing, "imu_ring");
  checkRing(edge_ring, kMaxSampleRing, "edge_ring");
  checkRing(clock_ring, kMaxSampleRing, "clock_ring");
  checkRing(motion_ring, kMaxMotionRing, "motion_ring");
  if (!(idle_wait_ns > 0 && idle_wait_ns <= kMaxIdleWaitNs)) {
    throw Error("recorder option 'idle_wait_ns' must be in (0, 100 ms], got " + std::to_string(idle_wait_ns));
  }
  mcap.validate();
}

Recorder::Recorder(const std::filesystem::path& path, const RecordingHeader& header, const RecorderOptions& options)
    : path_(path),
      options_((options.validate(), options)),
      file_(options.mcap),
      frames_(options.frame_ring, framePrototype(header.calibration)),
      imu_(options.imu_ring),
      edges_(options.edge_ring),
      motion_(options.motion_ring),
      clocks_(options.clock_ring) {
  if (!file_.open(path, header)) throw Error("cannot record to " + path.string() + ": " + file_.error());
  snapshot_.recording = true;
  thread_ = std::thread([this] { run(); });
}

Recorder::~Recorder() { stop(); }

bool Recorder::pushFrame(const RgbdFrame& frame) {
  if (accepting_.load(std::memory_order_acquire) && frames_.tryPush(frame)) return true;
  frames_lost_.fetch_add(1, std::memory_order_relaxed);
  return false;
}

bool Recorder::pushImu(const ImuSample& sample) {
  if (accepting_.load(std::memory_order_acquire) && imu_.tryPush(sample)) return true;
  imu_lost_.fetch_add(1, std::memory_order_relaxed);
  return false;
}

bool Recorder::pushSyncEdge(std::int64_t t_ns, bool rising, std::uint64_t sequence) {
  if (accepting_.load(std::memory_order_acquire) && edges_.tryPush(SyncEdgeItem{t_ns, rising, sequence})) return true;
  edges_lost_.fetch_add(1, std::memory_order_relaxed);
  return false;
}

bool Recorder::pushMotionTransfer(std::int64_t host_receive_ns, std::uint32_t index,
                                  std::span<const std::uint8_t> bytes) {
  if (accepting_.load(std::memory_order_acquire)) {
    motion_item_.host_receive_ns = host_receive_ns;
    motion_item_.index = index;
    motion_item_.size = std::min(bytes.size(), motion_item_.bytes.size());
    std::copy_n(bytes.begin(), motion_item_.size, motion_item_.bytes.begin());
    if (motion_.tryPush(motion_item_)) return true;
  }
  motion_lost_.fetch_add(1, std::memory_order_relaxed);
  return false;
}

bool Recorder::pushClock(const ClockRecord& clock) {
  if (accepting_.load(std::memory_order_acquire) && clocks_.tryPush(clock)) return true;
  clocks_lost_.fetch_add(1, std::memory_order_relaxed);
  return false;
}

bool Recorder::drain() {
  bool any = false;
  const bool writing = !file_.failed();
  // IMU, edges and clocks first: they are small and a frame's samples should precede it in the file.
  while (const ImuSample* sample = imu_.front()) {
    if (writing) file_.writeImu(*sample, monotonicNowNs());
    imu_.pop();
    any = true;
  }
  while (const SyncEdgeItem* edge = edges_.front()) {
    if (writing) file_.writeSyncEdge(edge->t_ns, edge->rising, edge->sequence, monotonicNowNs());
    edges_.pop();
    any = true;
  }
  while (const ClockRecord* clock = clocks_.front()) {
    if (writing) file_.writeClock(*clock, monotonicNowNs());
    clocks_.pop();
    any = true;
  }
  while (const MotionTransferItem* transfer = motion_.front()) {
    if (writing) {
      file_.writeMotionTransfer(transfer->host_receive_ns, transfer->index,
                                std::span<const std::uint8_t>(transfer->bytes.data(), transfer->size),
                                monotonicNowNs());
    }
    motion_.pop();
    any = true;
  }
  while (const RgbdFrame* frame = frames_.front()) {
    if (writing) file_.writeFrame(*frame, monotonicNowNs());
    frames_.pop();
    any = true;
  }
  return any;
}

void Recorder::noteFailure() { accepting_.store(false, std::memory_order_release); }

void Recorder::run() {
  while (!stop_.load(std::memory_order_acquire)) {
    const bool any = drain();
    if (!file_.failed()) file_.flushIfDue(monotonicNowNs());
    if (file_.failed()) noteFailure();
    {
      const std::lock_guard lock(stats_mutex_);
      snapshot_.failed = file_.failed();
      if (snapshot_.failed && snapshot_.error.empty()) snapshot_.error = file_.error();
      snapshot_.recording = !snapshot_.failed;
      snapshot_.written = file_.counts();
      snapshot_.bytes_written = file_.bytesWritten();
      snapshot_.messages_in_chunks = file_.messagesWritten();
      snapshot_.thread_cpu_ns = currentThreadCpuTimeNs();
    }
    if (!any) std::this_thread::sleep_for(std::chrono::nanoseconds(options_.idle_wait_ns));
  }
}

bool Recorder::stop() {
  if (stopped_) return closed_ok_;
  stopped_ = true;
  accepting_.store(false, std::memory_order_release);
  stop_.store(true, std::memory_order_release);
  if (thread_.joinable()) thread_.join();
  drain();  // what was pushed before accepting_ turned false
  closed_ok_ = file_.close();
  const std::lock_guard lock(stats_mutex_);
  snapshot_.recording = false;
  snapshot_.failed = !closed_ok_;
  if (snapshot_.failed && snapshot_.error.empty()) snapshot_.error = file_.error();
  snapshot_.written = file_.counts();
  snapshot_.bytes_written = file_.bytesWritten();
  snapshot_.messages_in_chunks = file_.messagesWritten();
  return closed_ok_;
}

RecorderStats Recorder::stats() const {
  RecorderStats copy;
  {
    const std::lock_guard lock(stats_mutex_);
    copy = snapshot_;
  }
  copy.frames_dropped = frames_lost_.load(std::memory_order_relaxed);
  copy.imu_dropped = imu_lost_.load(std::memory_order_relaxed);
  copy.edges_dropped = edges_lost_.load(std::memory_order_relaxed);
  copy.clocks_dropped = clocks_lost_.load(std::memory_order_relaxed);
  copy.motion_dropped = motion_lost_.load(std::memory_order_relaxed);
  return copy;
}

}  // namespace vifusion::recording
