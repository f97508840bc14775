#pragma once
// A GPIO chip (/dev/gpiochip0, 8 lines) emulated by umockdev, whose v1 character-device ioctls a handler
// answers, so the REAL libgpiod 1.6 (LibgpiodLineIo) opens it, reads its line count, requests edge events
// and reads them. The handler speaks the v1 uAPI (linux/gpio.h): GPIO_GET_CHIPINFO_IOCTL,
// GPIO_GET_LINEINFO_IOCTL and GPIO_GET_LINEEVENT_IOCTL, whose answer is a file descriptor of the line's
// events: here the read end of a pipe in this process, into which emitEdge() writes gpioevent_data records
// laid out as the uAPI documents them (u64 timestamp in ns, u32 event id), as the kernel would.
//
// Needs LD_PRELOAD=libumockdev-preload (the test runs under umockdev-wrapper).

#include <cstdint>
#include <memory>
#include <string>

namespace vifusion::gpio_sync::test {

class UmockdevGpioChip {
 public:
  static constexpr const char* kChipName = "gpiochip0";
  static constexpr unsigned kLineCount = 8;
  /// A line the emulated chip reports as held by another consumer.
  static constexpr unsigned kBusyLine = 6;
  static constexpr const char* kBusyConsumer = "gpio-keys";

  UmockdevGpioChip();
  ~UmockdevGpioChip();
  UmockdevGpioChip(const UmockdevGpioChip&) = delete;
  UmockdevGpioChip& operator=(const UmockdevGpioChip&) = delete;

  /// Writes one event record for the requested line: `t_ns` as the kernel's timestamp [ns], `rising` as
  /// GPIOEVENT_EVENT_RISING_EDGE, else GPIOEVENT_EVENT_FALLING_EDGE (or `raw_id` when non-zero).
  void emitEdge(std::uint64_t t_ns, bool rising, std::uint32_t raw_id = 0);
  /// Closes the writing end of the event pipe: the reader sees end-of-file, as after a failed device.
  void hangUp();
  /// What the last GPIO_GET_LINEEVENT_IOCTL asked for.
  unsigned requestedLine() const;
  std::uint32_t requestedEventFlags() const;
  std::string requestedConsumer() const;
  /// Event requests served so far.
  int eventRequests() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace vifusion::gpio_sync::test
