// The packet bytes against the documented layout (sensors.md §1.4), checked byte by byte so that the
// encoder and the parser cannot agree on a wrong layout: the encoder's output is compared with offsets
// written out here, and the parser reads bytes placed here by hand.

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

#include "packet_fixtures.hpp"
#include "vifusion/motion/packet_encoder.hpp"
#include "vifusion/motion/packet_parser.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion::motion {
namespace {

using test::encode;
using test::imuEntry;
using test::timestampEntry;

TEST(PacketLayout, GeometryIsTheDocumentedOne) {
  EXPECT_EQ(kPacketBytes, 104u);
  EXPECT_EQ(kImuSlotsOffset, 8u);
  EXPECT_EQ(kTimestampSlotsOffset, 56u);
  EXPECT_EQ(kMaxPacketsPerTransfer, 9u);  // 1024-byte interrupt buffer
}

TEST(PacketLayout, EncoderPlacesEveryFieldAtItsOffset) {
  MotionPacket packet;
  packet.header.error_bitmask = 0x1234;
  packet.header.power_mode_change_done = true;
  packet.header.cx3_packet_counter = 0xB;
  packet.header.imu_entry_count = 4;
  packet.header.timestamp_entry_count = 8;
  // Tag = source | counter << 3 | valid << 15: gyro (2), counter 0xABC, valid → 0x8000 | 0x55E0 | 2 = 0xD5E2.
  packet.imu[0] = imuEntry(EventSource::kGyroscope, 0xABC, 0x89ABCDEF, {-2, 0x1234, -32768});
  packet.imu[3] = imuEntry(EventSource::kAccelerometer, 1, 0x01020304, {0x7FF0, 0, 16});
  packet.imu[3].valid = false;
  packet.timestamps[0] = timestampEntry(EventSource::kDepthFrame, 0xFFF, 0xCAFEBABE);
  packet.timestamps[7] = timestampEntry(EventSource::kGpio2, 5, 0x00000001);

  const std::vector<std::uint8_t> bytes = encode(packet);
  ASSERT_EQ(bytes.size(), 104u);
  // Header: error bitmask, status (bit 1 + counter 0xB << 2 = 0x2E), counts, all little-endian.
  const std::array<std::uint8_t, 8> header{0x34, 0x12, 0x2E, 0x00, 0x04, 0x00, 0x08, 0x00};
  EXPECT_TRUE(std::equal(header.begin(), header.end(), bytes.begin()));
  // IMU slot 0 at 8: tag 0xD5E2, ticks 0x89ABCDEF, x −2, y 0x1234, z −32768.
  const std::array<std::uint8_t, 12> imu0{0xE2, 0xD5, 0xEF, 0xCD, 0xAB, 0x89, 0xFE, 0xFF, 0x34, 0x12, 0x00, 0x80};
  EXPECT_TRUE(std::equal(imu0.begin(), imu0.end(), bytes.begin() + 8));
  // IMU slot 3 at 8 + 36 = 44: accel (1), counter 1, valid clear → tag 0x0009.
  const std::array<std::uint8_t, 12> imu3{0x09, 0x00, 0x04, 0x03, 0x02, 0x01, 0xF0, 0x7F, 0x00, 0x00, 0x10, 0x00};
  EXPECT_TRUE(std::equal(imu3.begin(), imu3.end(), bytes.begin() + 44));
  // Timestamp slot 0 at 56: depth (3), counter 0xFFF, valid → 0x8000 | 0x7FF8 | 3 = 0xFFFB.
  const std::array<std::uint8_t, 6> ts0{0xFB, 0xFF, 0xBE, 0xBA, 0xFE, 0xCA};
  EXPECT_TRUE(std::equal(ts0.begin(), ts0.end(), bytes.begin() + 56));
  // Timestamp slot 7 at 56 + 42 = 98 (the last 6 bytes): GPIO2 (7), counter 5 → 0x8000 | 0x28 | 7 = 0x802F.
  const std::array<std::uint8_t, 6> ts7{0x2F, 0x80, 0x01, 0x00, 0x00, 0x00};
  EXPECT_TRUE(std::equal(ts7.begin(), ts7.end(), bytes.begin() + 98));
}

TEST(PacketLayout, ParserReadsHandPlacedBytes) {
  std::vector<std::uint8_t> bytes(kPacketBytes, 0);
  bytes[2] = 0x02 | (9 << 2);  // status: power-mode change done, CX3 counter 9
  bytes[4] = 1;                // one IMU entry
  bytes[6] = 1;                // one timestamp entry
  // IMU slot 0: accel, counter 100 (tag 0x8000 | 100 << 3 | 1 = 0x8321), ticks 4000000000, x = −16, y = 32, z = 0x7FF0.
  const std::array<std::uint8_t, 12> imu{0x21, 0x83, 0x00, 0x28, 0x6B, 0xEE, 0xF0, 0xFF, 0x20, 0x00, 0xF0, 0x7F};
  std::copy(imu.begin(), imu.end(), bytes.begin() + 8);
  // Timestamp slot 0: fisheye (4), frame 4095 → 0x8000 | 0x7FF8 | 4 = 0xFFFC, ticks 0xFFFFFFFF.
  const std::array<std::uint8_t, 6> ts{0xFC, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF};
  std::copy(ts.begin(), ts.end(), bytes.begin() + 56);

  PacketParser parser;
  ParsedTransfer out;
  EXPECT_EQ(parser.parse(bytes, out), 0u);
  ASSERT_EQ(out.headers().size(), 1u);
  EXPECT_TRUE(out.headers()[0].power_mode_change_done);
  EXPECT_EQ(out.headers()[0].cx3_packet_counter, 9);
  ASSERT_EQ(out.imuEntries().size(), 1u);
  const ImuEntry& entry = out.imuEntries()[0];
  EXPECT_EQ(entry.source, EventSource::kAccelerometer);
  EXPECT_EQ(entry.sample_counter, 100);
  EXPECT_TRUE(entry.valid);
  EXPECT_EQ(entry.ticks, 4000000000u);
  EXPECT_EQ(entry.raw_xyz[0], -16);
  EXPECT_EQ(entry.raw_xyz[1], 32);
  EXPECT_EQ(entry.raw_xyz[2], 0x7FF0);
  ASSERT_EQ(out.timestampEntries().size(), 1u);
  EXPECT_EQ(out.timestampEntries()[0].source, EventSource::kFisheyeFrame);
  EXPECT_EQ(out.timestampEntries()[0].frame_counter, 4095);
  EXPECT_EQ(out.timestampEntries()[0].ticks, 0xFFFFFFFFu);
}

TEST(PacketLayout, EncoderRefusesFieldsTooWideForTheirBits) {
  MotionPacket packet;
  packet.imu[2].sample_counter = 4096;
  std::array<std::uint8_t, kPacketBytes> bytes{};
  vifusion::test::expectError([&] { encodePacket(packet, bytes); }, "IMU slot 2 tag sample_counter = 4096");
  packet = {};
  packet.timestamps[5].source = static_cast<EventSource>(8);
  vifusion::test::expectError([&] { encodePacket(packet, bytes); }, "timestamp slot 5 tag source code = 8");
  packet = {};
  packet.header.cx3_packet_counter = 16;
  vifusion::test::expectError([&] { encodePacket(packet, bytes); }, "header cx3_packet_counter = 16");
  const std::array<MotionPacket, 2> two{};
  std::array<std::uint8_t, kPacketBytes + 1> small{};
  vifusion::test::expectError([&] { encodeTransfer(two, small); }, "2 packets need 208 B but the buffer holds 105 B");
}

TEST(PacketLayout, NamesOfSourcesAndErrorFlags) {
  EXPECT_EQ(eventSourceName(EventSource::kDepthFrame), "depth_frame");
  EXPECT_EQ(eventSourceName(EventSource::kGpio1), "gpio1");
  EXPECT_EQ(eventSourceName(static_cast<EventSource>(0)), "invalid");
  EXPECT_EQ(errorFlagName(ErrorFlag::kImuNotResponding), "imu_not_responding");
  EXPECT_EQ(errorFlagName(ErrorFlag::kCx3FifoOverflow), "cx3_fifo_overflow");
  EXPECT_EQ(errorFlagName(ErrorFlag::kReserved15), "reserved_bit_15");
  // Every flag has its own name.
  for (std::size_t a = 0; a < kErrorFlagCount; ++a) {
    for (std::size_t b = a + 1; b < kErrorFlagCount; ++b) {
      EXPECT_NE(errorFlagName(static_cast<ErrorFlag>(a)), errorFlagName(static_cast<ErrorFlag>(b)));
    }
  }
}

}  // namespace
}  // namespace vifusion::motion
