#pragma once
// A scripted ZR300 behind the live source's Zr300Backend, for end-to-end tests of `vifusion run --source zr300`
// without a camera: the in-memory V4L2 device (v4l2_scripted) serves the IR, depth and colour nodes, a
// scripted motion module behind the UsbLink seam answers the adapter commands and streams interrupt
// transfers, and both run on one ManualClock, so the whole stream replays as fast as the pipeline takes it
// and every timestamp is reproducible.
//
// Bytes come from the documented layouts only: Z16 with the DS4 metadata row (ds_metadata.hpp), YUYV with the
// colour frame number, motion packets from motion::encodeTransfer. What the script asks for is what a real
// device would have delivered: depth in whole Z16 units, colour through YUYV (expectedRgb() gives the colour
// after that round trip), IMU readings in whole counts (RawImu), all times on whole microseconds, which are
// exact in 32 MHz ticks and in the TUM text stamps of a recording.
//
// Time: the host clock (CLOCK_MONOTONIC stand-in) is the ManualClock. Frame k's motion-module event is at
// frame_t_ns[k]; its kernel buffer stamp 5 ms earlier (so a frame that fell back to the kernel time shows);
// its buffer completes kArrivalDelayNs after the event. IMU transfer i arrives at its sample's time (no USB
// latency: the clock mapping is then exact); the device's 32-bit tick counter starts 5 s before its wrap.
// Every poll of a V4L2 node waits until the motion module has received every transfer due by the clock's
// new time: USB transfers arrive as time passes, whatever the threads' real-time scheduling.

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "vifusion/core/image.hpp"
#include "vifusion/core/rig_calibration.hpp"
#include "vifusion/core/sensor_data.hpp"
#include "vifusion/v4l2_scripted/scripted_v4l2_device.hpp"
#include "vifusion/zr300/zr300_backend.hpp"
#include "vifusion/zr300/zr300_options.hpp"

namespace vifusion::live_test {

/// One IMU reading as the motion module sends it: gyro and accelerometer words at one tick.
struct RawImu {
  std::int64_t t_ns = 0;                ///< host time, whole µs
  std::array<std::int16_t, 3> gyro{};   ///< counts (±1000 °/s at ±32767)
  std::array<std::int16_t, 3> accel{};  ///< words: 12-bit counts << 4 (±4 g at ±2048)
};

/// The reading in SI units, as the driver's ImuScaler makes it (default ranges).
ImuSample toImuSample(const RawImu& raw);
/// The nearest raw reading of `sample` (saturating), at its time floored to whole µs.
RawImu toRawImu(const ImuSample& sample);

struct CameraScript {
  zr300::StreamPreset preset{320, 240, 30};
  std::uint32_t depth_units_um = 200;    ///< 1/5000 m, the unit of TUM-style recordings
  std::vector<std::int64_t> frame_t_ns;  ///< event times, whole µs, ≈ one frame period apart
  /// Frame k's depth in Z16 units, (W − 12)×(H − 12): the image inside the DS4's padding.
  std::function<void(int k, ImageView<std::uint16_t> inner)> depth;
  /// Frame k's colour before YUYV encoding, W×H.
  std::function<void(int k, ImageView<Rgb8> rgb)> colour;
  std::vector<RawImu> imu;                   ///< strictly increasing times, whole µs, ending after the last frame
  std::optional<std::int64_t> unplug_at_ns;  ///< the camera vanishes (both USB devices) at this host time
  std::optional<std::int64_t> replug_at_ns;  ///< and comes back at this one
  /// Frames lost before the host, depth and colour both (V4L2 sequence and DS4 counter skip them); their
  /// motion-module events still come, as when a USB transfer of the images fails.
  std::vector<int> lost_frames;
  /// Called on the polling thread with the clock's time after every poll of a V4L2 node (after the motion
  /// module caught up): another scripted device on the same clock (a sync line) catches up here, before any
  /// frame of that moment is dequeued. Empty: none.
  std::function<void(std::int64_t now_ns)> after_poll;
};

/// First DS4 frame counter: not 0, and past 4096, so the 12-bit event numbers wrap during a run.
inline constexpr std::uint32_t kFirstFrameCounter = 4000;
inline constexpr std::int64_t kArrivalDelayNs = 20'000'000;
inline constexpr std::int64_t kKernelStampBeforeEventNs = 5'000'000;

/// RGB → YUYV (BT.601 limited range, chroma of a pixel pair averaged): the camera's side of the encoding.
void rgbToYuyv(ImageView<const Rgb8> rgb, std::span<std::uint8_t> yuyv, std::uint32_t bytes_per_line);
/// What the live source delivers for a frame showing `rgb` with DS4 counter `counter`: YUYV-encoded, the frame
/// number written into the last 32 luma bytes, decoded again by the driver's decoder.
void expectedRgb(ImageView<const Rgb8> rgb, std::uint32_t counter, ImageView<Rgb8> out);

class ScriptedMotionLink;

class ScriptedCamera final : public zr300::Zr300Backend {
 public:
  explicit ScriptedCamera(CameraScript script);
  ~ScriptedCamera() override;

  discovery::Zr300Camera findCamera(const discovery::Zr300SourceSpec& spec,
                                    const discovery::CameraCheckOptions& options) override;
  v4l2::DeviceIo& deviceIo() override;
  std::unique_ptr<usb_imu::UsbLink> motionLink(const discovery::Zr300Camera& camera,
                                               std::size_t transfers_in_flight) override;
  void follow(const discovery::Zr300Camera&) override {}
  /// Time passes while the service waits: the clock moves on by `timeout_ns`, or to the replug if that comes
  /// first (a udev "add" event ends the wait).
  bool waitForHotplug(std::int64_t timeout_ns) override;

  v4l2_scripted::ManualClock& clock() { return clock_; }
  bool pluggedAt(std::int64_t t_ns) const;
  const CameraScript& script() const { return script_; }
  /// Transfers the motion module received, over every link.
  std::size_t transfersDelivered() const { return delivered_.load(); }
  /// CPU time spent making frames (the camera's side: filling and encoding buffers) [ns], which runs on the
  /// thread that polls the V4L2 nodes; a benchmark subtracts it from the driver's thread time.
  std::int64_t producerCpuNs() const { return producer_cpu_ns_.load(); }
  /// Adapter commands the driver sent, over every link (opcode values).
  std::vector<std::uint32_t> commandsSeen() const;

 private:
  class SyncedIo;
  friend class ScriptedMotionLink;
  void buildTransfers();
  /// Blocks (real time, bounded) until the current link has taken every transfer due by the clock's now.
  void waitForMotionCatchUp();

  CameraScript script_;
  v4l2_scripted::ManualClock clock_;
  std::unique_ptr<v4l2_scripted::ScriptedV4l2Device> device_;
  std::unique_ptr<SyncedIo> io_;
  // The motion stream, encoded once: transfer i's bytes and its arrival time.
  std::vector<std::uint8_t> transfer_bytes_;
  std::vector<std::size_t> transfer_offsets_;
  std::vector<std::int64_t> transfer_host_ns_;
  std::atomic<ScriptedMotionLink*> link_{nullptr};
  std::atomic<std::size_t> delivered_{0};
  std::atomic<std::int64_t> producer_cpu_ns_{0};
  mutable std::mutex commands_mutex_;
  std::vector<std::uint32_t> commands_;
};

}  // namespace vifusion::live_test
