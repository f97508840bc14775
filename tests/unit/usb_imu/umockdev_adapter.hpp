#pragma once
// The ZR300 adapter board (8086:0ad0) as a umockdev usbfs node whose ioctls a handler answers, so the REAL
// libusb (LibusbLink: libusb_wrap_sys_device, claim, bulk and interrupt URBs) runs against it. The
// handler speaks usbdevfs: SUBMITURB / REAPURBNDELAY / DISCARDURB, plus the set-up ioctls libusb 1.0.26
// issues (GET_CAPABILITIES, CONNECTINFO, GET_SPEED, CLAIM/RELEASEINTERFACE, and GETDRIVER/IOCTL answered
// ENODATA: no kernel driver bound). Bytes come from a
// ScriptedMotionDevice (command replies, interrupt transfers); interrupt URBs complete in real time at
// the script's transfer period, so host arrival times are real. After `unplug_after` interrupt transfers
// every ioctl fails with ENODEV, as the kernel's usbfs does for a vanished device.
//
// Needs LD_PRELOAD=libumockdev-preload (the test runs under umockdev-wrapper).

#include <cstddef>
#include <memory>
#include <string>

#include "scripted_motion_device.hpp"

namespace vifusion::usb_imu::test {

class UmockdevAdapter {
 public:
  static constexpr const char* kDevnode = "/dev/bus/usb/001/005";

  explicit UmockdevAdapter(const ScriptOptions& script);
  ~UmockdevAdapter();
  UmockdevAdapter(const UmockdevAdapter&) = delete;
  UmockdevAdapter& operator=(const UmockdevAdapter&) = delete;

  ScriptedMotionDevice& device();
  std::size_t interruptUrbsCompleted() const;
  std::size_t urbsSubmitted() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace vifusion::usb_imu::test
