// Adapter-board command framing (bulk OUT 0x01 / IN 0x81) and the power sequence, against the documented
// layout: u16 length after the first 4 bytes, u16 magic 0xCDAB, u32 opcode, 4 × u32 params, payload.

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

#include "vifusion/motion/adapter_command.hpp"
#include "vifusion/motion/power_sequence.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion::motion {
namespace {

using vifusion::test::expectError;

TEST(AdapterCommand, RequestBytesFollowTheDocumentedLayout) {
  std::array<std::uint8_t, kMaxCommandBytes> out{};
  const AdapterRequest power_on{.opcode = AdapterOpcode::kMotionModulePower, .params = {1, 0, 0, 0}, .payload = {}};
  ASSERT_EQ(encodeRequest(power_on, out), 24u);
  const std::array<std::uint8_t, 24> expected{0x14, 0x00, 0xAB, 0xCD, 0x0A, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00,
                                              0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00};
  EXPECT_TRUE(std::equal(expected.begin(), expected.end(), out.begin()));

  // Parameters in order, little-endian; a payload after the header; length counts both.
  const std::array<std::uint8_t, 3> payload{0xDE, 0xAD, 0x42};
  const AdapterRequest i2c_write{
      .opcode = AdapterOpcode::kI2cWrite, .params = {0x42, 0x58, 4, 0x01020304}, .payload = payload};
  ASSERT_EQ(encodeRequest(i2c_write, out), 27u);
  EXPECT_EQ(out[0], 23);  // 27 − 4
  EXPECT_EQ(out[4], 0x02);
  EXPECT_EQ(out[8], 0x42);
  EXPECT_EQ(out[12], 0x58);
  EXPECT_EQ(out[16], 4);
  EXPECT_EQ(out[20], 0x04);
  EXPECT_EQ(out[23], 0x01);
  EXPECT_EQ(out[24], 0xDE);
  EXPECT_EQ(out[26], 0x42);

  const AdapterRequest decoded = decodeRequest(std::span(out).first(27));
  EXPECT_EQ(decoded.opcode, AdapterOpcode::kI2cWrite);
  EXPECT_EQ(decoded.params, i2c_write.params);
  ASSERT_EQ(decoded.payload.size(), 3u);
  EXPECT_EQ(decoded.payload[1], 0xAD);
}

TEST(AdapterCommand, RequestProblemsAreNamed) {
  std::array<std::uint8_t, kMaxCommandBytes + 8> out{};
  const std::vector<std::uint8_t> too_much(kMaxRequestPayloadBytes + 1, 0);
  expectError([&] { encodeRequest({.opcode = AdapterOpcode::kCalibration, .payload = too_much}, out); },
              "adapter command 0x11 (MM_TRB): payload of 1001 B exceeds the maximum 1000 B");
  expectError([&] { encodeRequest({}, std::span(out).first(10)); }, "request needs 24 B but the buffer holds 10 B");

  ASSERT_EQ(encodeRequest({.opcode = AdapterOpcode::kGetVersion, .params = {}, .payload = {}}, out), 24u);
  expectError([&] { decodeRequest(std::span(out).first(20)); },
              "adapter request of 20 B is shorter than its 24-byte header");
  expectError([&] { decodeRequest(std::span(out).first(25)); },
              "length field 20 disagrees with the 21 B after the magic");
  expectError([&] { decodeRequest(out); }, "adapter request of 1032 B exceeds the maximum 1024 B");
  out[4] = 0x0F;
  expectError([&] { decodeRequest(std::span(out).first(24)); },
              "adapter request opcode 0x0F (unknown) is not a documented adapter command");
  out[3] = 0xCE;
  expectError([&] { decodeRequest(std::span(out).first(24)); }, "adapter request magic 0xCEAB is not 0xCDAB");
}

TEST(AdapterCommand, ReplyEchoesTheOpcodeThenData) {
  std::array<std::uint8_t, kMaxCommandBytes> out{};
  const std::array<std::uint8_t, 5> data{1, 2, 3, 4, 5};
  ASSERT_EQ(encodeReply(AdapterOpcode::kSerialNumber, data, out), 9u);
  const std::array<std::uint8_t, 4> echo{0x10, 0x00, 0x00, 0x00};
  EXPECT_TRUE(std::equal(echo.begin(), echo.end(), out.begin()));
  const std::span<const std::uint8_t> reply = decodeReply(AdapterOpcode::kSerialNumber, std::span(out).first(9), 5);
  ASSERT_EQ(reply.size(), 5u);
  EXPECT_EQ(reply[4], 5);
  // A bare echo is a complete reply to a command without data (MMPWR, MM_ACTIVATE).
  ASSERT_EQ(encodeReply(AdapterOpcode::kMotionModuleActivate, {}, out), 4u);
  EXPECT_TRUE(decodeReply(AdapterOpcode::kMotionModuleActivate, std::span(out).first(4)).empty());
}

TEST(AdapterCommand, ReplyProblemsAreNamed) {
  std::array<std::uint8_t, kMaxCommandBytes + 1> out{};
  ASSERT_EQ(encodeReply(AdapterOpcode::kDepthPower, {}, out), 4u);
  expectError([&] { decodeReply(AdapterOpcode::kMotionModulePower, std::span(out).first(4)); },
              "adapter reply echoes opcode 0x0B (DSPWR) for a request 0x0A (MMPWR)");
  expectError([&] { decodeReply(AdapterOpcode::kDepthPower, std::span(out).first(3)); },
              "adapter reply to 0x0B (DSPWR) is 3 B, shorter than its 4-byte echoed opcode");
  expectError([&] { decodeReply(AdapterOpcode::kDepthPower, out); },
              "adapter reply to 0x0B (DSPWR) is 1025 B, above the maximum 1024 B");
  expectError([&] { decodeReply(AdapterOpcode::kDepthPower, std::span(out).first(10), 32); },
              "adapter reply to 0x0B (DSPWR) holds 6 B of data, expected at least 32 B");
  const std::vector<std::uint8_t> too_much(kMaxReplyDataBytes + 1, 0);
  expectError([&] { encodeReply(AdapterOpcode::kGetVersion, too_much, out); },
              "data of 1021 B exceeds the maximum 1020 B");
}

TEST(AdapterCommand, OpcodesAreTheDocumentedOnes) {
  EXPECT_TRUE(isAdapterOpcode(0x01));
  EXPECT_TRUE(isAdapterOpcode(0x0E));
  EXPECT_FALSE(isAdapterOpcode(0x0F));
  EXPECT_TRUE(isAdapterOpcode(0x10));
  EXPECT_TRUE(isAdapterOpcode(0x11));
  EXPECT_FALSE(isAdapterOpcode(0x00));
  EXPECT_FALSE(isAdapterOpcode(0x12));
  EXPECT_EQ(adapterOpcodeName(AdapterOpcode::kMotionModuleActivate), "MM_ACTIVATE");
  EXPECT_EQ(static_cast<std::uint32_t>(AdapterOpcode::kMotionModulePower), 0x0Au);
}

TEST(PowerSequence, StartPowersUpWaits300MsThenActivates) {
  // Reset to a known state first, then MMPWR = 1, 300 ms, MM_ACTIVATE = 1.
  ASSERT_EQ(kStartImuSequence.size(), 4u);
  EXPECT_EQ(kStartImuSequence[0].opcode, AdapterOpcode::kMotionModuleActivate);
  EXPECT_EQ(kStartImuSequence[0].param, 0u);
  EXPECT_EQ(kStartImuSequence[1].opcode, AdapterOpcode::kMotionModulePower);
  EXPECT_EQ(kStartImuSequence[1].param, 0u);
  EXPECT_EQ(kStartImuSequence[2].opcode, AdapterOpcode::kMotionModulePower);
  EXPECT_EQ(kStartImuSequence[2].param, 1u);
  EXPECT_EQ(kStartImuSequence[2].wait_after_ns, 300'000'000);
  EXPECT_EQ(kStartImuSequence[3].opcode, AdapterOpcode::kMotionModuleActivate);
  EXPECT_EQ(kStartImuSequence[3].param, 1u);
  EXPECT_EQ(kStopImuSequence[0].opcode, AdapterOpcode::kMotionModuleActivate);
  EXPECT_EQ(kStopImuSequence[1].opcode, AdapterOpcode::kMotionModulePower);

  // Each step becomes a request as the USB module would send it.
  std::array<std::uint8_t, kMaxCommandBytes> out{};
  ASSERT_EQ(encodeRequest(kStartImuSequence[3].request(), out), 24u);
  EXPECT_EQ(out[4], 0x0E);
  EXPECT_EQ(out[8], 1);
}

}  // namespace
}  // namespace vifusion::motion
