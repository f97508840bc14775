#include "scripted_camera.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include "vifusion/clock/tick_clock.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/core/thread_cpu_time.hpp"
#include "vifusion/discovery/discovery_error.hpp"
#include "vifusion/motion/adapter_command.hpp"
#include "vifusion/motion/imu_scaling.hpp"
#include "vifusion/motion/packet_encoder.hpp"
#include "vifusion/v4l2/ds_metadata.hpp"
#include "vifusion/v4l2/fourcc.hpp"
#include "vifusion/v4l2/yuyv.hpp"

namespace vifusion::live_test {
namespace {

constexpr const char* kInfraredNode = "/dev/video0";
constexpr const char* kDepthNode = "/dev/video1";
constexpr const char* kColourNode = "/dev/video2";
constexpr const char* kAdapterNode = "/dev/bus/usb/001/003";
constexpr const char* kSerial = "SN_0000000001";
/// The motion module's tick counter this long before its 32-bit wrap at the clock's start [µs].
constexpr std::int64_t kTicksBeforeWrapUs = 5'000'000;
constexpr std::int64_t kTicksPerUs = clock::kZr300MotionTicksPerSecond / 1'000'000;
constexpr std::int64_t kClockLeadNs = 100'000'000;  ///< the clock starts this long before the first event
constexpr std::int64_t kIdlePumpSleepUs = 200;
constexpr double kCatchUpLimitS = 10.0;  ///< longest real-time wait for the motion module to catch up
constexpr std::uint16_t kCounterMask = motion::kTagCounterMask;

std::uint8_t clampByte(double value) { return static_cast<std::uint8_t>(std::clamp(std::lround(value), 0l, 255l)); }

std::int64_t floorToUs(std::int64_t t_ns) { return t_ns / 1000 * 1000; }

discovery::VideoNodeInfo videoNode(const char* devnode, int interface_number) {
  discovery::VideoNodeInfo node;
  node.devnode = devnode;
  node.syspath = std::string("/sys/devices/scripted/1-1:1.") + std::to_string(interface_number) + "/video4linux";
  node.interface_number = interface_number;
  return node;
}

}  // namespace

ImuSample toImuSample(const RawImu& raw) {
  static const motion::ImuScaler scaler;
  ImuSample sample;
  sample.t_ns = raw.t_ns;
  sample.gyro_rad_s = scaler.gyroRadS(raw.gyro);
  sample.accel_mps2 = scaler.accelMps2(raw.accel);
  return sample;
}

RawImu toRawImu(const ImuSample& sample) {
  static const motion::ImuScaler scaler;
  RawImu raw;
  raw.t_ns = floorToUs(sample.t_ns);
  for (int i = 0; i < 3; ++i) {
    const long gyro = std::lround(sample.gyro_rad_s[i] / scaler.gyroRadSPerCount());
    raw.gyro[i] = static_cast<std::int16_t>(std::clamp(gyro, -32767l, 32767l));
    const long accel = std::lround(sample.accel_mps2[i] / scaler.accelMps2PerCount());
    raw.accel[i] = static_cast<std::int16_t>(std::clamp(accel, -2048l, 2047l) * (1 << motion::kAccelDataShiftBits));
  }
  return raw;
}

void rgbToYuyv(ImageView<const Rgb8> rgb, std::span<std::uint8_t> yuyv, std::uint32_t bytes_per_line) {
  // BT.601 limited range, the inverse of the decoder's equations (yuyv.hpp).
  for (int y = 0; y < rgb.height; ++y) {
    std::uint8_t* row = yuyv.data() + static_cast<std::size_t>(y) * bytes_per_line;
    for (int x = 0; x + 1 < rgb.width; x += 2) {
      double cb = 0.0, cr = 0.0;
      for (int i = 0; i < 2; ++i) {
        const Rgb8 p = rgb(x + i, y);
        const double luma = 16.0 + (65.481 * p.r + 128.553 * p.g + 24.966 * p.b) / 255.0;
        row[2 * (x + i)] = clampByte(luma);
        cb += 128.0 + (-37.797 * p.r - 74.203 * p.g + 112.0 * p.b) / 255.0;
        cr += 128.0 + (112.0 * p.r - 93.786 * p.g - 18.214 * p.b) / 255.0;
      }
      row[2 * x + 1] = clampByte(cb / 2.0);
      row[2 * x + 3] = clampByte(cr / 2.0);
    }
  }
}

void expectedRgb(ImageView<const Rgb8> rgb, std::uint32_t counter, ImageView<Rgb8> out) {
  const auto bytes_per_line = static_cast<std::uint32_t>(2 * rgb.width);
  std::vector<std::uint8_t> yuyv(static_cast<std::size_t>(bytes_per_line) * static_cast<std::size_t>(rgb.height));
  rgbToYuyv(rgb, yuyv, bytes_per_line);
  v4l2::writeColourFrameNumber(counter, yuyv, bytes_per_line, rgb.width, rgb.height);
  v4l2::ProblemText problem;
  if (!v4l2::yuyvToRgb(yuyv, bytes_per_line, out, problem)) throw Error(problem.c_str());
}

// ---- the motion module behind the UsbLink seam ----

class ScriptedMotionLink final : public usb_imu::UsbLink {
 public:
  explicit ScriptedMotionLink(ScriptedCamera& camera) : camera_(camera) {}
  ~ScriptedMotionLink() override {
    ScriptedMotionLink* self = this;
    camera_.link_.compare_exchange_strong(self, nullptr);
  }

  usb_imu::UsbStatus open(int) override {
    const std::int64_t now = camera_.clock_.nowNs();
    if (!camera_.pluggedAt(now)) return usb_imu::UsbStatus::kNoDevice;
    // Transfers due before the device (re)appeared were never sent.
    const auto& hosts = camera_.transfer_host_ns_;
    next_.store(static_cast<std::size_t>(std::upper_bound(hosts.begin(), hosts.end(), now) - hosts.begin()));
    return usb_imu::UsbStatus::kOk;
  }

  usb_imu::UsbStatus bulkWrite(std::uint8_t, std::span<const std::uint8_t> bytes, int) override {
    if (!camera_.pluggedAt(camera_.clock_.nowNs())) return usb_imu::UsbStatus::kNoDevice;
    const motion::AdapterRequest request = motion::decodeRequest(bytes);
    {
      const std::lock_guard lock(camera_.commands_mutex_);
      camera_.commands_.push_back(static_cast<std::uint32_t>(request.opcode));
    }
    reply_size_ = motion::encodeReply(request.opcode, {}, reply_);
    return usb_imu::UsbStatus::kOk;
  }

  usb_imu::UsbStatus bulkRead(std::uint8_t endpoint, std::span<std::uint8_t> buffer, std::size_t& received,
                              int) override {
    received = 0;
    if (!camera_.pluggedAt(camera_.clock_.nowNs())) return usb_imu::UsbStatus::kNoDevice;
    if (endpoint != motion::kCommandInEndpoint || reply_size_ == 0) return usb_imu::UsbStatus::kTimeout;
    std::copy_n(reply_.begin(), reply_size_, buffer.begin());
    received = reply_size_;
    reply_size_ = 0;
    return usb_imu::UsbStatus::kOk;
  }

  usb_imu::UsbStatus startInterrupt(std::uint8_t, std::size_t, usb_imu::InterruptSink& sink) override {
    sink_ = &sink;
    camera_.link_.store(this);
    return usb_imu::UsbStatus::kOk;
  }

  usb_imu::UsbStatus pumpInterrupt(int) override {
    const std::int64_t now = camera_.clock_.nowNs();
    if (!camera_.pluggedAt(now)) return usb_imu::UsbStatus::kNoDevice;
    std::size_t next = next_.load();
    const std::size_t first = next;
    const auto& hosts = camera_.transfer_host_ns_;
    const auto& offsets = camera_.transfer_offsets_;
    for (; next < hosts.size() && hosts[next] <= now; ++next) {
      const std::size_t end = next + 1 < offsets.size() ? offsets[next + 1] : camera_.transfer_bytes_.size();
      sink_->onInterruptTransfer(std::span(camera_.transfer_bytes_).subspan(offsets[next], end - offsets[next]),
                                 hosts[next]);
      next_.store(next + 1);
      camera_.delivered_.fetch_add(1);
    }
    if (next == first) {
      std::this_thread::sleep_for(std::chrono::microseconds(kIdlePumpSleepUs));
      return usb_imu::UsbStatus::kTimeout;
    }
    return usb_imu::UsbStatus::kOk;
  }

  void stopInterrupt() override {
    ScriptedMotionLink* self = this;
    camera_.link_.compare_exchange_strong(self, nullptr);
    sink_ = nullptr;
  }
  void close() override {}

  /// Whether every transfer due by `now` has been handed to the driver.
  bool caughtUp(std::int64_t now) const {
    const std::size_t next = next_.load();
    return next >= camera_.transfer_host_ns_.size() || camera_.transfer_host_ns_[next] > now;
  }

 private:
  ScriptedCamera& camera_;
  std::atomic<std::size_t> next_{0};
  usb_imu::InterruptSink* sink_ = nullptr;
  std::array<std::uint8_t, motion::kMaxCommandBytes> reply_{};
  std::size_t reply_size_ = 0;
};

// ---- the V4L2 side ----

class ScriptedCamera::SyncedIo final : public v4l2::DeviceIo {
 public:
  SyncedIo(ScriptedCamera& camera, v4l2::DeviceIo& inner) : camera_(camera), inner_(inner) {}
  int open(const char* path, int flags) override { return inner_.open(path, flags); }
  int close(int fd) override { return inner_.close(fd); }
  int ioctl(int fd, unsigned long request, void* argument) override { return inner_.ioctl(fd, request, argument); }
  void* mmap(void* address, std::size_t length, int protection, int flags, int fd, off_t offset) override {
    return inner_.mmap(address, length, protection, flags, fd, offset);
  }
  int munmap(void* address, std::size_t length) override { return inner_.munmap(address, length); }
  int poll(pollfd* fds, nfds_t count, int timeout_ms) override {
    const int ready = inner_.poll(fds, count, timeout_ms);
    camera_.waitForMotionCatchUp();
    if (camera_.script_.after_poll) camera_.script_.after_poll(camera_.clock_.nowNs());
    return ready;
  }

 private:
  ScriptedCamera& camera_;
  v4l2::DeviceIo& inner_;
};

ScriptedCamera::ScriptedCamera(CameraScript script)
    : script_(std::move(script)),
      clock_(std::min(script_.frame_t_ns.front(),
                      script_.imu.empty() ? script_.frame_t_ns.front() : script_.imu.front().t_ns) -
             kClockLeadNs) {
  const int width = script_.preset.width_px;
  const int height = script_.preset.height_px;
  zr300::Zr300Options layout;
  layout.preset = script_.preset;
  const int inner_width = layout.depthNodeWidthPx();
  const int inner_height = layout.depthNodeHeightPx() - zr300::kDepthMetadataRows;
  const std::int64_t period_ns = (1'000'000'000 + script_.preset.fps / 2) / script_.preset.fps;
  const auto frame_count = static_cast<std::int64_t>(script_.frame_t_ns.size());
  device_ = std::make_unique<v4l2_scripted::ScriptedV4l2Device>(clock_);

  v4l2_scripted::ScriptedNodeConfig infrared;
  infrared.path = kInfraredNode;
  infrared.formats = {{v4l2::kFourccGrey, width, height + 1, 0, {script_.preset.fps}}};
  infrared.schedule.produce = [](const v4l2_scripted::ScriptedFrameRequest&, v4l2_scripted::ScriptedFrame&) {};
  const std::uint32_t units = script_.depth_units_um;
  infrared.controls = {{2, 3, {0}, true},
                       {2,
                        4,
                        {static_cast<std::uint8_t>(units), static_cast<std::uint8_t>(units >> 8),
                         static_cast<std::uint8_t>(units >> 16), static_cast<std::uint8_t>(units >> 24)},
                        true},
                       {2, 8, {0}, true}};
  device_->addNode(infrared);

  const auto stampOf = [this](std::int64_t k) {
    return floorToUs(script_.frame_t_ns[static_cast<std::size_t>(k)] - kKernelStampBeforeEventNs);
  };
  const auto lost = [this](std::int64_t k) {
    return std::find(script_.lost_frames.begin(), script_.lost_frames.end(), k) != script_.lost_frames.end();
  };
  v4l2_scripted::ScriptedNodeConfig depth;
  depth.path = kDepthNode;
  depth.formats = {{v4l2::kFourccZ16, inner_width, inner_height + 1, 0, {script_.preset.fps}}};
  depth.schedule = {script_.frame_t_ns.front() + kArrivalDelayNs, period_ns, frame_count,
                    [this, inner_width, inner_height, stampOf, lost](const v4l2_scripted::ScriptedFrameRequest& request,
                                                                     v4l2_scripted::ScriptedFrame& frame) {
                      if (lost(request.frame_index)) {
                        frame.lost = true;
                        return;
                      }
                      const std::int64_t cpu_start_ns = currentThreadCpuTimeNs();
                      const std::uint32_t line = request.format.bytesperline;
                      auto* pixels = reinterpret_cast<std::uint16_t*>(request.payload.data());
                      script_.depth(static_cast<int>(request.frame_index),
                                    ImageView<std::uint16_t>(pixels, inner_width, inner_height, line / 2));
                      v4l2::Dinghy dinghy;
                      dinghy.magic = v4l2::kDinghyMagicDepth;
                      dinghy.frame_counter = kFirstFrameCounter + static_cast<std::uint32_t>(request.frame_index);
                      v4l2::writeDinghy(dinghy, request.payload, line, inner_height + 1);
                      frame.t_stamp_ns = stampOf(request.frame_index);
                      producer_cpu_ns_.fetch_add(currentThreadCpuTimeNs() - cpu_start_ns);
                    }};
  device_->addNode(depth);

  auto scratch = std::make_shared<Image<Rgb8>>(width, height);
  v4l2_scripted::ScriptedNodeConfig colour;
  colour.path = kColourNode;
  colour.formats = {{v4l2::kFourccYuyv, width, height, 0, {script_.preset.fps}}};
  colour.schedule = {script_.frame_t_ns.front() + kArrivalDelayNs, period_ns, frame_count,
                     [this, scratch, width, height, stampOf, lost](const v4l2_scripted::ScriptedFrameRequest& request,
                                                                   v4l2_scripted::ScriptedFrame& frame) {
                       if (lost(request.frame_index)) {
                         frame.lost = true;
                         return;
                       }
                       const std::int64_t cpu_start_ns = currentThreadCpuTimeNs();
                       script_.colour(static_cast<int>(request.frame_index), scratch->view());
                       rgbToYuyv(scratch->view(), request.payload, request.format.bytesperline);
                       v4l2::writeColourFrameNumber(
                           kFirstFrameCounter + static_cast<std::uint32_t>(request.frame_index), request.payload,
                           request.format.bytesperline, width, height);
                       frame.t_stamp_ns = stampOf(request.frame_index);
                       producer_cpu_ns_.fetch_add(currentThreadCpuTimeNs() - cpu_start_ns);
                     }};
  device_->addNode(colour);
  if (script_.unplug_at_ns) device_->scheduleUnplug(*script_.unplug_at_ns);
  if (script_.replug_at_ns) device_->scheduleReplug(*script_.replug_at_ns);
  io_ = std::make_unique<SyncedIo>(*this, *device_);
  buildTransfers();
}

ScriptedCamera::~ScriptedCamera() = default;

void ScriptedCamera::buildTransfers() {
  const std::int64_t base_ns = clock_.nowNs();
  const auto first_tick = static_cast<std::uint32_t>((std::int64_t{1} << 32) - kTicksBeforeWrapUs * kTicksPerUs);
  const auto tickAt = [&](std::int64_t t_ns) {
    return first_tick + static_cast<std::uint32_t>((t_ns - base_ns) / 1000 * kTicksPerUs);
  };
  std::uint16_t imu_counter = 0;
  std::size_t next_frame = 0;
  for (const RawImu& raw : script_.imu) {
    motion::MotionPacket packet;
    const std::uint32_t tick = tickAt(raw.t_ns);
    packet.imu[0] = {motion::EventSource::kAccelerometer, imu_counter, true, tick, raw.accel};
    packet.imu[1] = {motion::EventSource::kGyroscope, imu_counter, true, tick, raw.gyro};
    packet.header.imu_entry_count = 2;
    imu_counter = (imu_counter + 1) & kCounterMask;
    while (next_frame < script_.frame_t_ns.size() && script_.frame_t_ns[next_frame] <= raw.t_ns &&
           packet.header.timestamp_entry_count < motion::kTimestampSlotCount) {
      const auto counter = static_cast<std::uint16_t>((kFirstFrameCounter + next_frame) & kCounterMask);
      packet.timestamps[packet.header.timestamp_entry_count++] = {motion::EventSource::kDepthFrame, counter, true,
                                                                  tickAt(script_.frame_t_ns[next_frame])};
      ++next_frame;
    }
    const std::size_t offset = transfer_bytes_.size();
    transfer_bytes_.resize(offset + motion::kPacketBytes);
    motion::encodeTransfer(std::span(&packet, 1), std::span(transfer_bytes_).subspan(offset));
    transfer_offsets_.push_back(offset);
    transfer_host_ns_.push_back(raw.t_ns);
  }
}

bool ScriptedCamera::pluggedAt(std::int64_t t_ns) const {
  if (!script_.unplug_at_ns || t_ns < *script_.unplug_at_ns) return true;
  return script_.replug_at_ns && t_ns >= *script_.replug_at_ns;
}

discovery::Zr300Camera ScriptedCamera::findCamera(const discovery::Zr300SourceSpec& spec,
                                                  const discovery::CameraCheckOptions&) {
  if (!pluggedAt(clock_.nowNs())) {
    throw discovery::DiscoveryError(discovery::DiscoveryProblem::kNoCamera,
                                    "no ZR300 (8086:0acb) on any USB bus (the scripted camera is unplugged)");
  }
  if (!spec.serial.empty() && !discovery::serialMatches(spec.serial, kSerial)) {
    throw discovery::DiscoveryError(discovery::DiscoveryProblem::kSerialNotFound,
                                    "no ZR300 with serial '" + spec.serial + "' (found " + kSerial + ")");
  }
  discovery::Zr300Camera camera;
  camera.camera_usb = {"/sys/devices/scripted/1-1", "/devices/scripted/1-1", "/dev/bus/usb/001/002", 1, 2, kSerial};
  camera.capture_nodes = {videoNode(kInfraredNode, 0), videoNode(kDepthNode, 2), videoNode(kColourNode, 4)};
  discovery::Zr300Adapter adapter;
  adapter.usb = {"/sys/devices/scripted/1-2", "/devices/scripted/1-2", kAdapterNode, 1, 3, ""};
  camera.adapter = adapter;
  return camera;
}

v4l2::DeviceIo& ScriptedCamera::deviceIo() { return *io_; }

std::unique_ptr<usb_imu::UsbLink> ScriptedCamera::motionLink(const discovery::Zr300Camera&, std::size_t) {
  return std::make_unique<ScriptedMotionLink>(*this);
}

bool ScriptedCamera::waitForHotplug(std::int64_t timeout_ns) {
  // A replug within the wait is a udev "add" event: the wait ends then, as HotplugMonitor's would.
  const std::int64_t now = clock_.nowNs();
  // The wait takes as long in real time too, so that an observer of the service (its status, its health)
  // sees the camera absent for as long as the script says.
  if (script_.replug_at_ns && now < *script_.replug_at_ns && *script_.replug_at_ns <= now + timeout_ns) {
    std::this_thread::sleep_for(std::chrono::nanoseconds(*script_.replug_at_ns - now));
    clock_.advanceTo(*script_.replug_at_ns);
    return true;
  }
  std::this_thread::sleep_for(std::chrono::nanoseconds(timeout_ns));
  clock_.advanceBy(timeout_ns);
  return false;
}

void ScriptedCamera::waitForMotionCatchUp() {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(kCatchUpLimitS);
  while (std::chrono::steady_clock::now() < deadline) {
    const ScriptedMotionLink* link = link_.load();
    const std::int64_t now = clock_.nowNs();
    if (link == nullptr || !pluggedAt(now) || link->caughtUp(now)) return;
    std::this_thread::sleep_for(std::chrono::microseconds(kIdlePumpSleepUs));
  }
}

std::vector<std::uint32_t> ScriptedCamera::commandsSeen() const {
  const std::lock_guard lock(commands_mutex_);
  return commands_;
}

}  // namespace vifusion::live_test
