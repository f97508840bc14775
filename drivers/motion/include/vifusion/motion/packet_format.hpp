#pragma once
// The ZR300 motion module's interrupt-endpoint packet, as bytes (sensors.md §1.4; names of the error
// flags and sources from librealsense legacy v1.12.4 src/motion-module.h and include/librealsense/rs.h).
// Every multi-byte field is little-endian. One USB interrupt transfer holds N whole packets:
//
//   offset  size  field
//        0     2  error_bitmask        one bit per ErrorFlag; any bit set: the device declares the data bad
//        2     2  status               bit 1 power-mode change done, bits 2–5 CX3 packet counter (mod 16)
//        4     2  imu_entry_count      IMU slots in use, 0…4
//        6     2  timestamp_entry_count timestamp slots in use, 0…8
//        8  4×12  IMU slots            tag u16, ticks u32, x y z int16
//       56   8×6  timestamp slots      tag u16, ticks u32
//      104        (end)
//
// Tag (u16): bits 0–2 source code (EventSource), bits 3–14 a 12-bit per-source counter (IMU sample or frame
// number, wraps at 4096), bit 15 valid. Ticks: the microcontroller's free-running 32-bit counter at 32 MHz
// (31.25 ns, wraps every ≈134.2 s); converting and unwrapping them is the clock module's job.

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace vifusion::motion {

// ---- USB transport of the packets (the USB module opens these; defined here, once) ----
inline constexpr int kMotionInterfaceNumber = 2;             ///< vendor interface of the 0x0AD0 adapter board
inline constexpr std::uint8_t kImuInterruptEndpoint = 0x84;  ///< interrupt IN endpoint carrying the packets
/// Buffer of one interrupt transfer: what librealsense v1.12.4 reads; holds 9 whole packets.
inline constexpr std::size_t kMaxTransferBytes = 1024;

// ---- packet geometry ----
inline constexpr std::size_t kHeaderBytes = 8;
inline constexpr std::size_t kImuSlotCount = 4;
inline constexpr std::size_t kImuSlotBytes = 12;
inline constexpr std::size_t kTimestampSlotCount = 8;
inline constexpr std::size_t kTimestampSlotBytes = 6;
inline constexpr std::size_t kImuSlotsOffset = kHeaderBytes;
inline constexpr std::size_t kTimestampSlotsOffset = kImuSlotsOffset + kImuSlotCount * kImuSlotBytes;
inline constexpr std::size_t kPacketBytes = kTimestampSlotsOffset + kTimestampSlotCount * kTimestampSlotBytes;
static_assert(kPacketBytes == 104, "the documented packet is 104 bytes");
inline constexpr std::size_t kMaxPacketsPerTransfer = kMaxTransferBytes / kPacketBytes;

// ---- header fields (byte offsets within a packet) ----
inline constexpr std::size_t kErrorBitmaskOffset = 0;
inline constexpr std::size_t kStatusOffset = 2;
inline constexpr std::size_t kImuEntryCountOffset = 4;
inline constexpr std::size_t kTimestampEntryCountOffset = 6;
inline constexpr std::uint16_t kStatusPowerModeDoneBit = 1u << 1;
inline constexpr unsigned kStatusCx3CounterShift = 2;
inline constexpr std::uint16_t kCx3CounterMask = 0xF;  ///< 4-bit packet counter of the CX3 USB bridge
inline constexpr unsigned kCx3CounterModulus = kCx3CounterMask + 1;

// ---- slot fields (byte offsets within a slot) ----
inline constexpr std::size_t kSlotTagOffset = 0;
inline constexpr std::size_t kSlotTicksOffset = 2;
inline constexpr std::size_t kImuSlotAxesOffset = 6;  ///< x, y, z int16 at +6, +8, +10
inline constexpr std::size_t kAxisCount = 3;

// ---- tag bits ----
inline constexpr std::uint16_t kTagSourceMask = 0x7;
inline constexpr unsigned kTagCounterShift = 3;
inline constexpr std::uint16_t kTagCounterMask = 0xFFF;  ///< 12-bit counter, after the shift
inline constexpr std::uint16_t kTagValidBit = 1u << 15;
inline constexpr unsigned kCounterModulus = kTagCounterMask + 1;  ///< 4096: the 12-bit counters wrap here

/// Who produced a slot's entry: the tag's 3-bit source code as sent (librealsense's rs_event_source is
/// code − 1). Code 0 is not a source; codes 1–2 belong in IMU slots, 3–7 in timestamp slots.
enum class EventSource : std::uint8_t {
  kAccelerometer = 1,
  kGyroscope = 2,
  kDepthFrame = 3,    ///< a depth-camera frame (depth, IR and colour frames are matched to it)
  kFisheyeFrame = 4,  ///< a fisheye-camera frame (needs the fisheye strobe option on)
  kGpio0 = 5,         ///< external sync input G0
  kGpio1 = 6,
  kGpio2 = 7,
};
inline constexpr std::size_t kSourceCodeCount = kTagSourceMask + 1;  ///< codes 0…7, 0 unused

constexpr bool isImuSource(std::uint8_t code) {
  return code == static_cast<std::uint8_t>(EventSource::kAccelerometer) ||
         code == static_cast<std::uint8_t>(EventSource::kGyroscope);
}
constexpr bool isTimestampSource(std::uint8_t code) {
  return code >= static_cast<std::uint8_t>(EventSource::kDepthFrame) &&
         code <= static_cast<std::uint8_t>(EventSource::kGpio2);
}
/// "accelerometer", "gyroscope", "depth_frame", "fisheye_frame", "gpio0"…"gpio2", or "invalid".
std::string_view eventSourceName(EventSource source);

/// Bit positions in error_bitmask. The firmware documentation is not public; names follow librealsense
/// v1.12.4's motion_module_errors (bits 14 and 15 are reserved there). Any bit set drops the packet.
enum class ErrorFlag : std::uint8_t {
  kImuNotResponding = 0,
  kIllegalConfiguration = 1,
  kTimestampFifoOverflow = 2,
  kImuFifoOverflow = 3,
  kWatchdogReset = 4,
  kCrcError = 5,
  kMissingDataFromImu = 6,
  kBootloaderFailure = 7,
  kEepromError = 8,
  kBuiltInSelfTestFailed = 9,
  kMicrocontrollerNotResponding = 10,
  kCx3FifoOverflow = 11,
  kCx3GeneralFailure = 12,
  kCx3UsbFailure = 13,
  kReserved14 = 14,
  kReserved15 = 15,
};
inline constexpr std::size_t kErrorFlagCount = 16;

/// snake_case name of a flag, e.g. "imu_fifo_overflow".
std::string_view errorFlagName(ErrorFlag flag);

}  // namespace vifusion::motion
