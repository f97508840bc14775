#pragma once
// UVC extension-unit (XU) controls through uvcvideo's UVCIOC_CTRL_QUERY (linux/uvcvideo.h): a query names
// the unit, the control selector, the request (GET_CUR reads, SET_CUR writes) and the exact size of the
// control's value; uvcvideo answers ENOENT for a control it does not know and ENOBUFS for a wrong size.
//
// DS4 controls the pipeline needs (librealsense legacy v1.12.x src/ds-private.h/.cpp; sensors.md §1.3): all on
// the DS4 XU (GUID 18682D34-DD2C-4073-AD23-7214739A074C), unit 2, which librealsense addresses through the
// IR node (subdevice 0); values little-endian:
//   selector 3  stream intent, 1 byte: bit 0 depth (Z), bit 1 left/right IR, bit 2 colour — set before
//               streaming to the streams about to start;
//   selector 4  depth units, 4 bytes: µm per Z16 unit (default 1000 = 1 mm);
//   selector 8  emitter, 1 byte: write 1 on / 0 off; reads back bit 0 = on while streaming (librealsense
//               interprets bits 1 and 2 when idle, which is not needed here).

#include <cstdint>
#include <span>

#include "vifusion/v4l2/device_io.hpp"

namespace vifusion::v4l2 {

/// One XU control: where it is, how big its value is, and a name for messages.
struct XuControl {
  std::uint8_t unit = 0;
  std::uint8_t selector = 0;
  std::uint16_t size_bytes = 0;
  const char* name = "";
};

/// Reads the control's current value into `value` (exactly control.size_bytes long).
/// @throws DeviceError naming the control, unit, selector and errno; vifusion::Error for a wrong buffer size.
void xuGetCurrent(DeviceIo& io, int fd, const XuControl& control, std::span<std::uint8_t> value);
/// Sets the control's current value from `value` (exactly control.size_bytes long). Same errors.
void xuSetCurrent(DeviceIo& io, int fd, const XuControl& control, std::span<const std::uint8_t> value);

namespace ds4 {

inline constexpr std::uint8_t kXuUnit = 2;
inline constexpr XuControl kStreamIntent{kXuUnit, 3, 1, "DS4 stream intent"};
inline constexpr XuControl kDepthUnits{kXuUnit, 4, 4, "DS4 depth units"};
inline constexpr XuControl kEmitter{kXuUnit, 8, 1, "DS4 emitter"};

/// Stream-intent bits.
inline constexpr std::uint8_t kIntentDepth = 1u << 0;
inline constexpr std::uint8_t kIntentInfrared = 1u << 1;
inline constexpr std::uint8_t kIntentColour = 1u << 2;
/// Emitter byte: bit 0 is "on" (written, and read back while streaming).
inline constexpr std::uint8_t kEmitterOnBit = 1u << 0;
/// Firmware default and librealsense's nominal depth unit [µm].
inline constexpr std::uint32_t kDefaultDepthUnitsUm = 1000;

void setStreamIntent(DeviceIo& io, int fd, std::uint8_t intent_bits);
std::uint32_t depthUnitsUm(DeviceIo& io, int fd);
/// @throws vifusion::Error for 0 µm, DeviceError when the device refuses.
void setDepthUnitsUm(DeviceIo& io, int fd, std::uint32_t depth_units_um);
void setEmitterEnabled(DeviceIo& io, int fd, bool enabled);
/// The emitter byte's bit 0: meaningful while the depth stream runs.
bool emitterOnWhileStreaming(DeviceIo& io, int fd);

}  // namespace ds4
}  // namespace vifusion::v4l2
