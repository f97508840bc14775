#pragma once
// The ZR300 as a live source (`zr300`, `zr300:SERIAL`): a DatasetReader whose frames come from the camera
// as they are taken, and an ImuFeed over the motion module's IMU ring, so that `vifusion run` and vifusiond
// use it exactly like a recording.
//
// Construction (synchronous; its errors mean "no camera to use": exit code 3 in both programs):
//   backend.findCamera(spec) → XU controls on the IR node (stream intent depth + colour, depth units,
//   emitter) → depth (Z16) and colour (YUYV) V4l2Streams → the motion module (when options.imu).
// Then one camera thread assembles frames:
//   depth buffer → DS4 metadata row checked, its frame counter noted (dropped frames from its gaps) → Z16
//   into the centre of a zeroed W×H image (the DS4's 6-px padding) → the colour buffer with the same frame
//   number (colour numbers count depth frames; a lone frame on either side is counted and dropped) → YUYV to
//   RGB → stamped with the motion module's event for that depth frame (host CLOCK_MONOTONIC through the
//   device→host clock mapping), or, when no event comes within frame_event_wait_ns, with the depth buffer's
//   kernel mid-exposure time (counted: kernel_timestamps) → handed over through a ring of pre-sized frames.
// Frames and IMU samples share one clock, so the calibration's time_shift_cam_imu_ns is all that relates
// them. ASSUMED, not checked against a device: that the DS4 counter of a depth frame equals, modulo 4096,
// the number in the motion module's event for it, and that a colour frame's number equals the counter of
// the depth frame taken with it when both run at the same rate.
//
// Unplug (a stream or the motion module reports the device gone): every device is closed, the source
// reports the camera absent (stats().camera_present), and the thread waits for a hotplug event or its
// backoff and opens the camera again by the same spec; frames resume with new indices' times after the gap.
// nextFrame() just waits meanwhile; nothing already handed over is touched.
//
// Threads: nextFrame(), imuFeed() use on the consumer (SLAM/reader) thread; stats(), describe(),
// requestStop() from any thread. After start-up the camera thread allocates nothing.

#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "vifusion/core/live_imu_feed.hpp"
#include "vifusion/core/rig_calibration.hpp"
#include "vifusion/core/spsc_ring.hpp"
#include "vifusion/datasets/dataset_reader.hpp"
#include "vifusion/discovery/source_spec.hpp"
#include "vifusion/usb_imu/motion_module.hpp"
#include "vifusion/v4l2/problem_text.hpp"
#include "vifusion/v4l2/v4l2_stream.hpp"
#include "vifusion/zr300/frame_event_table.hpp"
#include "vifusion/zr300/zr300_backend.hpp"
#include "vifusion/zr300/zr300_options.hpp"
#include "vifusion/zr300/zr300_stats.hpp"

namespace vifusion::zr300 {

class Zr300Source final : public datasets::DatasetReader {
 public:
  /// Opens the camera `spec` names and starts streaming. `calibration` describes the rig (intrinsics at the
  /// preset's size, T_S_C, time shift, IMU noise); its depth_scale_m is replaced by the camera's depth unit.
  /// @throws discovery::DiscoveryError (no such camera, or a missing part), vifusion::Error (a device that
  /// refuses the preset, a calibration for another image size, bad options).
  Zr300Source(std::unique_ptr<Zr300Backend> backend, const discovery::Zr300SourceSpec& spec,
              const RigCalibration& calibration, const Zr300Options& options);
  ~Zr300Source() override;
  Zr300Source(const Zr300Source&) = delete;
  Zr300Source& operator=(const Zr300Source&) = delete;

  const RigCalibration& calibration() const override { return calibration_; }
  /// A live source does not know how many frames will come: 0.
  std::size_t frameCount() const override { return 0; }
  bool live() const override { return true; }
  /// Waits for the next assembled frame; false once requestStop() was called.
  bool nextFrame(RgbdFrame& frame) override;
  std::string describe() const override;

  /// The IMU samples for each frame (inertial modes); nullptr when options.imu is false.
  ImuFeed* imuFeed() { return imu_feed_ ? &*imu_feed_ : nullptr; }
  const LiveImuFeed* liveImuFeed() const { return imu_feed_ ? &*imu_feed_ : nullptr; }
  Zr300Stats stats() const;
  /// The motion module's transfers as received, for a recorder (consumer thread); nullptr without the IMU. Empty
  /// unless options.motion.raw_transfer_ring_capacity > 0. The same ring across unplug and re-open.
  SpscRing<usb_imu::RawTransfer>* rawTransferRing() { return motion_ ? &motion_->rawTransferRing() : nullptr; }
  /// Samples waiting in the motion module's IMU ring, and its capacity (0, 0 without the IMU); any thread.
  std::size_t imuRingFill() const { return motion_ ? motion_->imuRing().size() : 0; }
  std::size_t imuRingCapacity() const { return motion_ ? motion_->imuRing().capacity() : 0; }
  /// CPU time the driver threads (camera assembly and motion module) have used so far [ns].
  std::int64_t driverCpuNs() const;
  /// Why the camera is absent or the last frame was refused; empty when nothing went wrong.
  std::string lastProblem() const;
  /// Asks the camera thread to end; nextFrame() returns false from then on. Only stores a flag, so a signal
  /// handler may call it; the destructor joins the thread and closes the devices.
  void requestStop() noexcept { stop_.store(true, std::memory_order_release); }

 private:
  enum class Step { kContinue, kDeviceGone };

  void openDevices();
  void closeDevices() noexcept;
  void cameraLoop();
  bool reopen(std::int64_t& backoff_ns);
  Step assembleFrame();
  /// Fills pending_.rgb from the colour frame numbered `counter`; false when there is none.
  bool takeColour(std::uint32_t counter, Step& step);
  std::int64_t frameTime(std::uint32_t counter, std::int64_t kernel_mid_ns);
  bool motionGone() const;
  void noteProblem(const char* format, ...) __attribute__((format(printf, 2, 3)));
  template <class F>
  void updateStats(F&& change) {
    const std::lock_guard lock(stats_mutex_);
    change(stats_);
  }

  std::unique_ptr<Zr300Backend> backend_;
  discovery::Zr300SourceSpec spec_;
  Zr300Options options_;
  RigCalibration calibration_;
  discovery::Zr300Camera camera_;
  std::uint32_t depth_units_um_ = 0;

  int infrared_fd_ = -1;
  std::optional<v4l2::V4l2Stream> depth_;
  std::optional<v4l2::V4l2Stream> colour_;
  std::unique_ptr<usb_imu::MotionModule> motion_;
  std::optional<LiveImuFeed> imu_feed_;
  v4l2::BorrowedFrame held_colour_;  ///< a colour frame ahead of the depth stream, kept for the next depth frame
  std::uint32_t held_colour_number_ = 0;

  FrameEventTable events_;
  RgbdFrame pending_;
  SpscRing<RgbdFrame> frames_;
  std::int64_t next_index_ = 0;
  std::int64_t last_t_ns_ = 0;

  std::atomic<bool> stop_{false};
  std::thread thread_;
  mutable std::mutex stats_mutex_;
  Zr300Stats stats_;
  v4l2::ProblemText problem_;  ///< guarded by stats_mutex_
};

}  // namespace vifusion::zr300
