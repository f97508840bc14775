#pragma once
// The few USB operations the motion-module driver needs, behind one interface: LibusbLink (libusb_link.hpp)
// moves real bytes; a scripted link in the tests plays the device. The seam sits at this level, not at
// the raw usbdevfs ioctls, because the driver's logic (command framing, power sequence, per-transfer
// decode, unplug handling) is what must be tested without hardware, and libusb's own URB handling is
// libusb's concern.
//
// Results are UsbStatus values, not exceptions: the per-transfer path must not throw, and "the device
// was unplugged" is an expected state for a robot, not an error (MotionModule turns it into kUnplugged).

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

namespace vifusion::usb_imu {

enum class UsbStatus : std::uint8_t {
  kOk,
  kTimeout,       ///< nothing arrived within the timeout (an idle endpoint is not a failure)
  kNoDevice,      ///< the device is gone (LIBUSB_ERROR_NO_DEVICE): unplugged
  kAccessDenied,  ///< the node or interface could not be opened or claimed for lack of permission
  kBusy,          ///< another process holds the interface
  kOverflow,      ///< the device sent more than the buffer holds
  kIoError,       ///< any other transfer or driver failure
};

/// snake_case name, e.g. "no_device".
std::string_view usbStatusName(UsbStatus status);

/// Receives completed interrupt transfers on the driver thread (the thread that calls pumpInterrupt).
class InterruptSink {
 public:
  virtual ~InterruptSink() = default;
  /// `bytes` is valid only during the call; `host_receive_ns` is CLOCK_MONOTONIC when the transfer
  /// completed, the arrival time that the clock mapper pairs with the transfer's newest device tick.
  virtual void onInterruptTransfer(std::span<const std::uint8_t> bytes, std::int64_t host_receive_ns) = 0;
};

class UsbLink {
 public:
  virtual ~UsbLink() = default;

  /// Opens the device and claims `interface_number`. Set-up: may allocate.
  virtual UsbStatus open(int interface_number) = 0;
  /// Bulk OUT of all of `bytes` to `endpoint` within `timeout_ms`.
  virtual UsbStatus bulkWrite(std::uint8_t endpoint, std::span<const std::uint8_t> bytes, int timeout_ms) = 0;
  /// Bulk IN from `endpoint` into `buffer`; `received` is set to the byte count.
  virtual UsbStatus bulkRead(std::uint8_t endpoint, std::span<std::uint8_t> buffer, std::size_t& received,
                             int timeout_ms) = 0;
  /// Submits the interrupt-IN transfers on `endpoint` (buffers of `transfer_bytes`, sized at open time),
  /// which complete into `sink` from pumpInterrupt() and are resubmitted there.
  virtual UsbStatus startInterrupt(std::uint8_t endpoint, std::size_t transfer_bytes, InterruptSink& sink) = 0;
  /// Waits up to `timeout_ms` for completions and delivers them to the sink. kTimeout when none came;
  /// kNoDevice once the device is gone. Per-transfer path: allocates nothing of ours.
  virtual UsbStatus pumpInterrupt(int timeout_ms) = 0;
  /// Cancels the interrupt transfers and waits until none is in flight. Safe after an unplug.
  virtual void stopInterrupt() = 0;
  /// Releases the interface and closes the device. Safe to call twice and after an unplug.
  virtual void close() = 0;
};

}  // namespace vifusion::usb_imu
