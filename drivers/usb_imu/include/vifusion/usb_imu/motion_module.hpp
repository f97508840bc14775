#pragma once
// The ZR300 motion module as a driver thread: opens the adapter board through a UsbLink, claims interface
// 2, runs the power/activation sequence (motion::kStartImuSequence) over bulk OUT 0x01 / IN 0x81, then
// streams interrupt transfers on 0x84 through a TransferDecoder into two rings the consumer pops:
//   imuRing()        merged ImuSamples on host CLOCK_MONOTONIC,
//   frameEventRing() depth-frame events (frame number + host ns) for the camera side to match frames,
//   rawTransferRing() the transfers as received, when options.raw_transfer_ring_capacity > 0 (recordings).
//
// Why async transfers with a fixed pool (LibusbLink) rather than a blocking read loop: libusb's blocking
// libusb_interrupt_transfer() allocates a libusb_transfer on every call, and between two blocking reads
// nothing polls the endpoint, so a burst can be lost on the device side. A pool of transfers_in_flight
// transfers allocated at start keeps the endpoint polled while one is decoded, and our code allocates
// nothing per transfer. (libusb 1.0.26 itself still callocs its URB array in each submission on Linux.)
//
// Unplug: any LIBUSB_ERROR_NO_DEVICE (kNoDevice) ends the stream in state kUnplugged, never an exception;
// stop() is then still safe (it skips the power-down commands the device can no longer take), and the
// service waits for a hotplug event and calls start() again. Other failures leave kFailed and lastError().
//
// Threads: start(), stop() and the destructor on one owning thread; the rings' consumer side on one
// consumer thread; state() and stats() from any thread.

#include <atomic>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <thread>

#include "vifusion/core/sensor_data.hpp"
#include "vifusion/core/spsc_ring.hpp"
#include "vifusion/motion/adapter_command.hpp"
#include "vifusion/motion/power_sequence.hpp"
#include "vifusion/usb_imu/frame_event.hpp"
#include "vifusion/usb_imu/motion_module_options.hpp"
#include "vifusion/usb_imu/motion_module_stats.hpp"
#include "vifusion/usb_imu/raw_transfer.hpp"
#include "vifusion/usb_imu/transfer_decoder.hpp"
#include "vifusion/usb_imu/usb_link.hpp"

namespace vifusion::usb_imu {

class MotionModule final : private InterruptSink {
 public:
  /// @throws vifusion::Error if options.validate() does or `link` is null.
  explicit MotionModule(std::unique_ptr<UsbLink> link, const MotionModuleOptions& options = {});
  /// Stops the stream (power-down commands unless unplugged) and closes the device.
  ~MotionModule() override;
  MotionModule(const MotionModule&) = delete;
  MotionModule& operator=(const MotionModule&) = delete;

  /// Opens, claims, runs the start sequence and starts the driver thread. Returns true when streaming,
  /// false when the device is gone (state kUnplugged). Calls stop() first if already started.
  /// @throws vifusion::Error naming the step for any other failure (permission, busy, a bad reply).
  bool start();
  /// Ends the thread, runs the stop sequence if the device is still there, releases and closes.
  /// Never throws; leaves kClosed, or kUnplugged if the device went away.
  void stop();
  /// Stops, then talks to the device through `link` from the next start(): a camera that came back after
  /// an unplug is a new USB device (new devnum, new usbfs node). The rings stay, so their consumers keep
  /// their references. @throws vifusion::Error if `link` is null.
  void replaceLink(std::unique_ptr<UsbLink> link);

  ModuleState state() const { return state_.load(std::memory_order_acquire); }
  /// CPU time the driver thread has used so far [ns]; 0 when it is not running. For benchmarks and status.
  std::int64_t threadCpuNs() const;
  /// Snapshot of every counter, readable from any thread.
  MotionModuleStats stats() const;
  /// What ended the stream in kFailed, or why start() threw; empty otherwise.
  std::string lastError() const;

  /// Consumer side of the rings (their capacities come from the options).
  SpscRing<ImuSample>& imuRing() { return imu_ring_; }
  SpscRing<DepthFrameEvent>& frameEventRing() { return frame_ring_; }
  SpscRing<RawTransfer>& rawTransferRing() { return raw_ring_; }

 private:
  void onInterruptTransfer(std::span<const std::uint8_t> bytes, std::int64_t host_receive_ns) override;
  /// Sends one adapter command and checks its reply; returns the link's status, throws on a bad reply.
  UsbStatus runStep(const motion::AdapterStep& step);
  template <std::size_t N>
  UsbStatus runSequence(const std::array<motion::AdapterStep, N>& steps);
  void threadMain();
  void setError(std::string message);

  MotionModuleOptions options_;
  std::unique_ptr<UsbLink> link_;
  SpscRing<ImuSample> imu_ring_;
  SpscRing<DepthFrameEvent> frame_ring_;
  SpscRing<RawTransfer> raw_ring_;  ///< one unused slot when raw transfers are not kept
  RawTransfer raw_;                 ///< the transfer being copied (driver thread)
  TransferDecoder decoder_;
  std::array<std::uint8_t, motion::kMaxCommandBytes> command_buffer_{};
  std::atomic<ModuleState> state_{ModuleState::kClosed};
  std::atomic<bool> running_{false};
  bool opened_ = false;
  std::thread thread_;
  mutable std::mutex error_mutex_;
  std::string last_error_;
};

}  // namespace vifusion::usb_imu
