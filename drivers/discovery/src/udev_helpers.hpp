#pragma once
// Small, allocation-free readers over libudev devices shared by the scan and the hotplug monitor, and
// owning handles for libudev's reference-counted objects.

#include <libudev.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>

namespace vifusion::discovery::detail {

struct UdevUnref {
  void operator()(udev* handle) const { udev_unref(handle); }
  void operator()(udev_device* handle) const { udev_device_unref(handle); }
  void operator()(udev_enumerate* handle) const { udev_enumerate_unref(handle); }
};
using UdevHandle = std::unique_ptr<udev, UdevUnref>;
using UdevDeviceHandle = std::unique_ptr<udev_device, UdevUnref>;
using UdevEnumerateHandle = std::unique_ptr<udev_enumerate, UdevUnref>;

/// A sysfs attribute of `device` ("" when absent or unreadable; libudev strips the trailing newline).
std::string_view sysattrOf(udev_device* device, const char* name);
/// A udev property (uevent variable or udev database entry) of `device`, "" when absent.
std::string_view propertyOf(udev_device* device, const char* name);

/// Base-10 non-negative integer that fits an int, the whole text; nullopt otherwise.
std::optional<int> parseDecimal(std::string_view text);
/// Hex digits (no prefix), the whole text, value ≤ max_value; nullopt otherwise.
std::optional<std::uint32_t> parseHex(std::string_view text, std::uint32_t max_value);

/// "/devices/…/4-2/4-2.1" → "/devices/…/4-2": a USB device's directory sits directly in its hub's.
/// "" when there is no '/' after the first character.
std::string_view parentDevpath(std::string_view devpath);
/// Whether `devpath` lies strictly below `ancestor` (a path-component prefix, not a text prefix:
/// "/d/4-2.1:1.0" is below "/d/4-2.1", "/d/4-2.10" is not). An empty ancestor contains nothing.
bool isBelow(std::string_view devpath, std::string_view ancestor);

struct UsbIds {
  std::uint16_t vendor = 0;
  std::uint16_t product = 0;
};
/// Vendor and product of a USB device: sysfs idVendor/idProduct, or, when sysfs is already gone (an event
/// read after the device left), the uevent's PRODUCT=vendor/product/bcdDevice (hex without leading zeros).
std::optional<UsbIds> usbIdsOf(udev_device* device);
/// sysfs `serial`, or udev's ID_SERIAL_SHORT when sysfs is gone; "" when the device has none.
std::string_view usbSerialOf(udev_device* device);

}  // namespace vifusion::discovery::detail
