#pragma once
// Command framing of the ZR300 adapter board (0x0AD0, interface 2): a request written to bulk OUT 0x01,
// ~20 ms later a reply read from bulk IN 0x81 (sensors.md §1.6). All fields little-endian:
//
//   request  offset 0  u16  length: bytes after the first 4 (20 + payload)
//                   2  u16  magic 0xCDAB
//                   4  u32  opcode
//                   8  4×u32 parameters
//                  24  …    payload (optional)
//   reply    offset 0  u32  the request's opcode, echoed
//                   4  …    data
//
// Both directions are at most kMaxCommandBytes. This file frames bytes only; the USB module moves them. The
// request decoder and reply encoder serve the scripted device of the integration tests. Commands are set-up
// traffic, not the per-sample path, so problems are thrown as vifusion::Error naming the field.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "vifusion/core/time.hpp"

namespace vifusion::motion {

inline constexpr std::uint8_t kCommandOutEndpoint = 0x01;  ///< bulk OUT: requests
inline constexpr std::uint8_t kCommandInEndpoint = 0x81;   ///< bulk IN: replies
/// Pause between writing a request and reading its reply (librealsense v1.12.4's value).
inline constexpr std::int64_t kReplyDelayNs = 20 * kNsPerMillisecond;

inline constexpr std::uint16_t kCommandMagic = 0xCDAB;
inline constexpr std::size_t kCommandParamCount = 4;
inline constexpr std::size_t kRequestLengthOffset = 0;
inline constexpr std::size_t kRequestMagicOffset = 2;
inline constexpr std::size_t kRequestOpcodeOffset = 4;
inline constexpr std::size_t kRequestParamsOffset = 8;
inline constexpr std::size_t kRequestHeaderBytes = kRequestParamsOffset + kCommandParamCount * sizeof(std::uint32_t);
/// The length field counts the bytes after itself and the magic.
inline constexpr std::size_t kRequestLengthExcludedBytes = kRequestOpcodeOffset;
inline constexpr std::size_t kReplyOpcodeBytes = 4;
inline constexpr std::size_t kMaxCommandBytes = 1024;  ///< the adapter's command buffer, either direction
inline constexpr std::size_t kMaxRequestPayloadBytes = kMaxCommandBytes - kRequestHeaderBytes;
inline constexpr std::size_t kMaxReplyDataBytes = kMaxCommandBytes - kReplyOpcodeBytes;

/// Adapter-board commands (librealsense v1.12.4 adaptor_board_command); 0x0F is not used.
enum class AdapterOpcode : std::uint32_t {
  kI2cRead = 0x01,               ///< IRB: read a microcontroller register (i2c slave 0x42)
  kI2cWrite = 0x02,              ///< IWB: write a microcontroller register
  kGetVersion = 0x03,            ///< GVD: firmware versions and dates
  kIapI2cRead = 0x04,            ///< IAP_IRB: i2c read in firmware-update mode
  kIapI2cWrite = 0x05,           ///< IAP_IWB: i2c write in firmware-update mode
  kFrameCounter = 0x06,          ///< FRCNT
  kGetLoggerData = 0x07,         ///< GLD
  kGpioWrite = 0x08,             ///< GPW
  kGpioRead = 0x09,              ///< GPR
  kMotionModulePower = 0x0A,     ///< MMPWR: motion module and fisheye power, param 1 = on / 0 = off
  kDepthPower = 0x0B,            ///< DSPWR: DS4 power
  kExternalTrigger = 0x0C,       ///< EXT_TRIG
  kCx3FirmwareUpdate = 0x0D,     ///< CX3FWUPD
  kMotionModuleActivate = 0x0E,  ///< MM_ACTIVATE: IMU event stream, param 1 = start / 0 = stop
  kSerialNumber = 0x10,          ///< MM_SNB
  kCalibration = 0x11,           ///< MM_TRB: intrinsics and extrinsics
};

/// True for the documented opcodes above.
bool isAdapterOpcode(std::uint32_t value);
/// Mnemonic as in the firmware tools ("MMPWR", "MM_ACTIVATE", …), or "unknown".
std::string_view adapterOpcodeName(AdapterOpcode opcode);

struct AdapterRequest {
  AdapterOpcode opcode = AdapterOpcode::kGetVersion;
  std::array<std::uint32_t, kCommandParamCount> params{};
  std::span<const std::uint8_t> payload;  ///< ≤ kMaxRequestPayloadBytes; views the caller's bytes
};

/// Bytes encodeRequest() writes for `request`.
constexpr std::size_t requestBytes(const AdapterRequest& request) {
  return kRequestHeaderBytes + request.payload.size();
}

/// Writes the request; returns the bytes written.
/// @throws vifusion::Error if the payload exceeds kMaxRequestPayloadBytes or `out` is too small.
std::size_t encodeRequest(const AdapterRequest& request, std::span<std::uint8_t> out);

/// Reads a request as the device would (payload views `bytes`).
/// @throws vifusion::Error naming the field: shorter than the header, longer than kMaxCommandBytes, wrong
///         magic, a length field that disagrees with the byte count, an undocumented opcode.
AdapterRequest decodeRequest(std::span<const std::uint8_t> bytes);

/// Writes a reply echoing `opcode` followed by `data`; returns the bytes written.
/// @throws vifusion::Error if data exceeds kMaxReplyDataBytes or `out` is too small.
std::size_t encodeReply(AdapterOpcode opcode, std::span<const std::uint8_t> data, std::span<std::uint8_t> out);

/// Checks a reply to a request with `expected` opcode and returns its data (a view into `reply`).
/// @throws vifusion::Error naming the problem: shorter than the 4-byte echo, longer than kMaxCommandBytes,
///         an echo of another opcode, or fewer than `min_data_bytes` of data.
std::span<const std::uint8_t> decodeReply(AdapterOpcode expected, std::span<const std::uint8_t> reply,
                                          std::size_t min_data_bytes = 0);

}  // namespace vifusion::motion
