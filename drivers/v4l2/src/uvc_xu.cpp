#include "vifusion/v4l2/uvc_xu.hpp"

#include <linux/usb/video.h>
#include <linux/uvcvideo.h>

#include <array>
#include <cerrno>
#include <string>

#include "vifusion/core/error.hpp"
#include "vifusion/v4l2/device_error.hpp"

namespace vifusion::v4l2 {
namespace {

constexpr int kBitsPerByte = 8;
constexpr std::size_t kDepthUnitsBytes = 4;

std::string describe(const XuControl& control, const char* request) {
  return std::string("UVC XU control '") + control.name + "' (unit " + std::to_string(control.unit) + ", selector " +
         std::to_string(control.selector) + ", " + std::to_string(control.size_bytes) + " bytes) " + request;
}

void query(DeviceIo& io, int fd, const XuControl& control, std::uint8_t request, const char* request_name,
           std::uint8_t* data, std::size_t data_bytes) {
  if (data_bytes != control.size_bytes) {
    throw Error(describe(control, request_name) + ": value buffer holds " + std::to_string(data_bytes) + " bytes");
  }
  uvc_xu_control_query xu_query{};
  xu_query.unit = control.unit;
  xu_query.selector = control.selector;
  xu_query.query = request;
  xu_query.size = control.size_bytes;
  xu_query.data = data;
  if (io.ioctl(fd, UVCIOC_CTRL_QUERY, &xu_query) < 0) {
    const int error_number = errno;
    std::string hint;
    if (error_number == ENOENT) hint = " (the device has no such control)";
    if (error_number == ENOBUFS) hint = " (the device's control has another size)";
    throw DeviceError(describe(control, request_name) + " failed" + hint, error_number);
  }
}

}  // namespace

void xuGetCurrent(DeviceIo& io, int fd, const XuControl& control, std::span<std::uint8_t> value) {
  query(io, fd, control, UVC_GET_CUR, "GET_CUR", value.data(), value.size());
}

void xuSetCurrent(DeviceIo& io, int fd, const XuControl& control, std::span<const std::uint8_t> value) {
  // UVCIOC_CTRL_QUERY takes a non-const pointer for both directions; SET_CUR only reads it. Copy so the
  // caller's bytes stay const.
  constexpr std::size_t kLargestInlineControl = 64;
  std::array<std::uint8_t, kLargestInlineControl> copy{};
  if (value.size() > copy.size()) {
    throw Error(describe(control, "SET_CUR") + ": value of " + std::to_string(value.size()) + " bytes is too large");
  }
  for (std::size_t i = 0; i < value.size(); ++i) copy[i] = value[i];
  query(io, fd, control, UVC_SET_CUR, "SET_CUR", copy.data(), value.size());
}

namespace ds4 {

void setStreamIntent(DeviceIo& io, int fd, std::uint8_t intent_bits) {
  const std::array<std::uint8_t, 1> value{intent_bits};
  xuSetCurrent(io, fd, kStreamIntent, value);
}

std::uint32_t depthUnitsUm(DeviceIo& io, int fd) {
  std::array<std::uint8_t, kDepthUnitsBytes> value{};
  xuGetCurrent(io, fd, kDepthUnits, value);
  std::uint32_t units = 0;
  for (std::size_t i = kDepthUnitsBytes; i-- > 0;) units = (units << kBitsPerByte) | value[i];
  return units;
}

void setDepthUnitsUm(DeviceIo& io, int fd, std::uint32_t depth_units_um) {
  if (depth_units_um == 0) throw Error(std::string(kDepthUnits.name) + ": 0 µm per unit would make every depth zero");
  std::array<std::uint8_t, kDepthUnitsBytes> value{};
  for (std::size_t i = 0; i < kDepthUnitsBytes; ++i) {
    value[i] = static_cast<std::uint8_t>(depth_units_um >> (kBitsPerByte * i));
  }
  xuSetCurrent(io, fd, kDepthUnits, value);
}

void setEmitterEnabled(DeviceIo& io, int fd, bool enabled) {
  const std::array<std::uint8_t, 1> value{enabled ? kEmitterOnBit : std::uint8_t{0}};
  xuSetCurrent(io, fd, kEmitter, value);
}

bool emitterOnWhileStreaming(DeviceIo& io, int fd) {
  std::array<std::uint8_t, 1> value{};
  xuGetCurrent(io, fd, kEmitter, value);
  return (value[0] & kEmitterOnBit) != 0;
}

}  // namespace ds4
}  // namespace vifusion::v4l2
