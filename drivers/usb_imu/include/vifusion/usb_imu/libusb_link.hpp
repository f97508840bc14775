#pragma once
// UsbLink over libusb 1.0 (built with VIFUSION_WITH_LIVE_DRIVERS only).
//
// How the device is opened: we open() the usbfs node discovery found (/dev/bus/usb/BBB/DDD, the adapter
// board 0x0AD0) ourselves and hand the fd to libusb_wrap_sys_device(), in a context created with
// LIBUSB_OPTION_NO_DEVICE_DISCOVERY, rather than enumerating the bus and matching busnum/devnum:
//  - the open that can fail for lack of permission is ours, so the error names the node (and the udev
//    rule / group that grants it) instead of a bare LIBUSB_ERROR_ACCESS;
//  - no enumeration of every device on the bus, no libusb hotplug thread (discovery's HotplugMonitor
//    already follows the camera through udev);
//  - the same fd is what the service could receive from a privileged helper later.
//
// Interrupt IN: transfers_in_flight libusb_transfers with their buffers, allocated in startInterrupt()
// and resubmitted from their completion callback, which runs inside pumpInterrupt() on the driver thread.

#include <cstdint>
#include <memory>
#include <string>

#include "vifusion/usb_imu/usb_link.hpp"

namespace vifusion::usb_imu {

class LibusbLink final : public UsbLink {
 public:
  /// `devnode`: the usbfs node of the adapter board; `transfers_in_flight` ≥ 1 (MotionModuleOptions).
  LibusbLink(std::string devnode, std::size_t transfers_in_flight);
  ~LibusbLink() override;
  LibusbLink(const LibusbLink&) = delete;
  LibusbLink& operator=(const LibusbLink&) = delete;

  UsbStatus open(int interface_number) override;
  UsbStatus bulkWrite(std::uint8_t endpoint, std::span<const std::uint8_t> bytes, int timeout_ms) override;
  UsbStatus bulkRead(std::uint8_t endpoint, std::span<std::uint8_t> buffer, std::size_t& received,
                     int timeout_ms) override;
  UsbStatus startInterrupt(std::uint8_t endpoint, std::size_t transfer_bytes, InterruptSink& sink) override;
  UsbStatus pumpInterrupt(int timeout_ms) override;
  void stopInterrupt() override;
  void close() override;

  /// The OS error of the last failed open() of the node (errno text naming the path), for messages.
  const std::string& openError() const { return open_error_; }

 private:
  struct State;  // libusb types stay out of this header
  std::string devnode_;
  std::size_t transfers_in_flight_;
  std::unique_ptr<State> state_;
  std::string open_error_;
};

}  // namespace vifusion::usb_imu
