#include "udev_helpers.hpp"

#include <charconv>
#include <limits>

namespace vifusion::discovery::detail {
namespace {

constexpr std::uint32_t kMaxUsbId = std::numeric_limits<std::uint16_t>::max();

std::string_view orEmpty(const char* text) { return text == nullptr ? std::string_view() : std::string_view(text); }

}  // namespace

std::string_view sysattrOf(udev_device* device, const char* name) {
  return orEmpty(udev_device_get_sysattr_value(device, name));
}

std::string_view propertyOf(udev_device* device, const char* name) {
  return orEmpty(udev_device_get_property_value(device, name));
}

std::optional<int> parseDecimal(std::string_view text) {
  int value = 0;
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(text.data(), end, value, 10);
  if (text.empty() || error != std::errc() || stop != end || value < 0) return std::nullopt;
  return value;
}

std::optional<std::uint32_t> parseHex(std::string_view text, std::uint32_t max_value) {
  std::uint32_t value = 0;
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(text.data(), end, value, 16);
  if (text.empty() || error != std::errc() || stop != end || value > max_value) return std::nullopt;
  return value;
}

std::string_view parentDevpath(std::string_view devpath) {
  const std::size_t slash = devpath.rfind('/');
  if (slash == std::string_view::npos || slash == 0) return {};
  return devpath.substr(0, slash);
}

bool isBelow(std::string_view devpath, std::string_view ancestor) {
  return !ancestor.empty() && devpath.size() > ancestor.size() + 1 && devpath.starts_with(ancestor) &&
         devpath[ancestor.size()] == '/';
}

std::optional<UsbIds> usbIdsOf(udev_device* device) {
  const auto vendor = parseHex(sysattrOf(device, "idVendor"), kMaxUsbId);
  const auto product = parseHex(sysattrOf(device, "idProduct"), kMaxUsbId);
  if (vendor && product) return UsbIds{static_cast<std::uint16_t>(*vendor), static_cast<std::uint16_t>(*product)};

  // PRODUCT=8086/acb/247c (kernel drivers/usb/core/driver.c usb_uevent()).
  const std::string_view product_variable = propertyOf(device, "PRODUCT");
  const std::size_t first = product_variable.find('/');
  if (first == std::string_view::npos) return std::nullopt;
  const std::size_t second = product_variable.find('/', first + 1);
  if (second == std::string_view::npos) return std::nullopt;
  const auto event_vendor = parseHex(product_variable.substr(0, first), kMaxUsbId);
  const auto event_product = parseHex(product_variable.substr(first + 1, second - first - 1), kMaxUsbId);
  if (!event_vendor || !event_product) return std::nullopt;
  return UsbIds{static_cast<std::uint16_t>(*event_vendor), static_cast<std::uint16_t>(*event_product)};
}

std::string_view usbSerialOf(udev_device* device) {
  const std::string_view serial = sysattrOf(device, "serial");
  return serial.empty() ? propertyOf(device, "ID_SERIAL_SHORT") : serial;
}

}  // namespace vifusion::discovery::detail
