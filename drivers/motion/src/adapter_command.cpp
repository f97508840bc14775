#include "vifusion/motion/adapter_command.hpp"

#include <algorithm>
#include <cstdio>
#include <string>

#include "little_endian.hpp"
#include "vifusion/core/error.hpp"

namespace vifusion::motion {
namespace {

using detail::readU16;
using detail::readU32;
using detail::writeU16;
using detail::writeU32;

std::string hex(std::uint32_t value, int digits) {
  char text[16];
  std::snprintf(text, sizeof(text), "0x%0*X", digits, value);
  return text;
}

/// "0x0A (MMPWR)", or "0x0F (unknown)".
std::string opcodeText(std::uint32_t value) {
  constexpr int kOpcodeDigits = 2;
  const std::string_view name =
      isAdapterOpcode(value) ? adapterOpcodeName(static_cast<AdapterOpcode>(value)) : "unknown";
  return hex(value, kOpcodeDigits) + " (" + std::string(name) + ")";
}

void requireRoom(std::size_t needed, std::size_t available, const char* what) {
  if (needed <= available) return;
  throw Error(std::string("adapter command: ") + what + " needs " + std::to_string(needed) +
              " B but the buffer holds " + std::to_string(available) + " B");
}

}  // namespace

bool isAdapterOpcode(std::uint32_t value) {
  constexpr std::uint32_t kFirst = static_cast<std::uint32_t>(AdapterOpcode::kI2cRead);
  constexpr std::uint32_t kLastContiguous = static_cast<std::uint32_t>(AdapterOpcode::kMotionModuleActivate);
  return (value >= kFirst && value <= kLastContiguous) ||
         value == static_cast<std::uint32_t>(AdapterOpcode::kSerialNumber) ||
         value == static_cast<std::uint32_t>(AdapterOpcode::kCalibration);
}

std::string_view adapterOpcodeName(AdapterOpcode opcode) {
  switch (opcode) {
    case AdapterOpcode::kI2cRead:
      return "IRB";
    case AdapterOpcode::kI2cWrite:
      return "IWB";
    case AdapterOpcode::kGetVersion:
      return "GVD";
    case AdapterOpcode::kIapI2cRead:
      return "IAP_IRB";
    case AdapterOpcode::kIapI2cWrite:
      return "IAP_IWB";
    case AdapterOpcode::kFrameCounter:
      return "FRCNT";
    case AdapterOpcode::kGetLoggerData:
      return "GLD";
    case AdapterOpcode::kGpioWrite:
      return "GPW";
    case AdapterOpcode::kGpioRead:
      return "GPR";
    case AdapterOpcode::kMotionModulePower:
      return "MMPWR";
    case AdapterOpcode::kDepthPower:
      return "DSPWR";
    case AdapterOpcode::kExternalTrigger:
      return "EXT_TRIG";
    case AdapterOpcode::kCx3FirmwareUpdate:
      return "CX3FWUPD";
    case AdapterOpcode::kMotionModuleActivate:
      return "MM_ACTIVATE";
    case AdapterOpcode::kSerialNumber:
      return "MM_SNB";
    case AdapterOpcode::kCalibration:
      return "MM_TRB";
  }
  return "unknown";
}

std::size_t encodeRequest(const AdapterRequest& request, std::span<std::uint8_t> out) {
  if (request.payload.size() > kMaxRequestPayloadBytes) {
    throw Error("adapter command " + opcodeText(static_cast<std::uint32_t>(request.opcode)) + ": payload of " +
                std::to_string(request.payload.size()) + " B exceeds the maximum " +
                std::to_string(kMaxRequestPayloadBytes) + " B");
  }
  const std::size_t total = requestBytes(request);
  requireRoom(total, out.size(), "request");
  writeU16(out, kRequestLengthOffset, static_cast<std::uint16_t>(total - kRequestLengthExcludedBytes));
  writeU16(out, kRequestMagicOffset, kCommandMagic);
  writeU32(out, kRequestOpcodeOffset, static_cast<std::uint32_t>(request.opcode));
  for (std::size_t i = 0; i < kCommandParamCount; ++i) {
    writeU32(out, kRequestParamsOffset + i * sizeof(std::uint32_t), request.params[i]);
  }
  std::copy(request.payload.begin(), request.payload.end(), out.begin() + kRequestHeaderBytes);
  return total;
}

AdapterRequest decodeRequest(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < kRequestHeaderBytes) {
    throw Error("adapter request of " + std::to_string(bytes.size()) + " B is shorter than its " +
                std::to_string(kRequestHeaderBytes) + "-byte header");
  }
  if (bytes.size() > kMaxCommandBytes) {
    throw Error("adapter request of " + std::to_string(bytes.size()) + " B exceeds the maximum " +
                std::to_string(kMaxCommandBytes) + " B");
  }
  const std::uint16_t magic = readU16(bytes, kRequestMagicOffset);
  if (magic != kCommandMagic) {
    throw Error("adapter request magic " + hex(magic, 4) + " is not " + hex(kCommandMagic, 4));
  }
  const std::uint16_t length = readU16(bytes, kRequestLengthOffset);
  if (length != bytes.size() - kRequestLengthExcludedBytes) {
    throw Error("adapter request length field " + std::to_string(length) + " disagrees with the " +
                std::to_string(bytes.size() - kRequestLengthExcludedBytes) + " B after the magic");
  }
  const std::uint32_t opcode = readU32(bytes, kRequestOpcodeOffset);
  if (!isAdapterOpcode(opcode)) {
    throw Error("adapter request opcode " + opcodeText(opcode) + " is not a documented adapter command");
  }
  AdapterRequest request;
  request.opcode = static_cast<AdapterOpcode>(opcode);
  for (std::size_t i = 0; i < kCommandParamCount; ++i) {
    request.params[i] = readU32(bytes, kRequestParamsOffset + i * sizeof(std::uint32_t));
  }
  request.payload = bytes.subspan(kRequestHeaderBytes);
  return request;
}

std::size_t encodeReply(AdapterOpcode opcode, std::span<const std::uint8_t> data, std::span<std::uint8_t> out) {
  if (data.size() > kMaxReplyDataBytes) {
    throw Error("adapter reply to " + opcodeText(static_cast<std::uint32_t>(opcode)) + ": data of " +
                std::to_string(data.size()) + " B exceeds the maximum " + std::to_string(kMaxReplyDataBytes) + " B");
  }
  const std::size_t total = kReplyOpcodeBytes + data.size();
  requireRoom(total, out.size(), "reply");
  writeU32(out, 0, static_cast<std::uint32_t>(opcode));
  std::copy(data.begin(), data.end(), out.begin() + kReplyOpcodeBytes);
  return total;
}

std::span<const std::uint8_t> decodeReply(AdapterOpcode expected, std::span<const std::uint8_t> reply,
                                          std::size_t min_data_bytes) {
  const std::string request = opcodeText(static_cast<std::uint32_t>(expected));
  if (reply.size() < kReplyOpcodeBytes) {
    throw Error("adapter reply to " + request + " is " + std::to_string(reply.size()) +
                " B, shorter than its 4-byte echoed opcode");
  }
  if (reply.size() > kMaxCommandBytes) {
    throw Error("adapter reply to " + request + " is " + std::to_string(reply.size()) + " B, above the maximum " +
                std::to_string(kMaxCommandBytes) + " B");
  }
  const std::uint32_t echoed = readU32(reply, 0);
  if (echoed != static_cast<std::uint32_t>(expected)) {
    throw Error("adapter reply echoes opcode " + opcodeText(echoed) + " for a request " + request);
  }
  const std::span<const std::uint8_t> data = reply.subspan(kReplyOpcodeBytes);
  if (data.size() < min_data_bytes) {
    throw Error("adapter reply to " + request + " holds " + std::to_string(data.size()) +
                " B of data, expected at least " + std::to_string(min_data_bytes) + " B");
  }
  return data;
}

}  // namespace vifusion::motion
