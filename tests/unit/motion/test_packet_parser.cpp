// The parser on encoder-made transfers: every field round-trips, and each kind of corrupt input is dropped,
// counted under its reason and described with the field's name.

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "packet_fixtures.hpp"
#include "vifusion/motion/packet_parser.hpp"
#include "vifusion/test/counting_allocations.hpp"

namespace vifusion::motion {
namespace {

using test::accelGyroPacket;
using test::encode;
using test::imuEntry;
using test::timestampEntry;

std::string text(const PacketProblem& problem) { return std::string(describe(problem).view()); }

/// A packet with all 4 IMU and all 8 timestamp slots in use and extreme values in every field.
MotionPacket fullPacket(std::uint16_t counter_base) {
  MotionPacket packet;
  packet.header.power_mode_change_done = true;
  packet.header.cx3_packet_counter = 15;
  packet.header.imu_entry_count = kImuSlotCount;
  packet.header.timestamp_entry_count = kTimestampSlotCount;
  packet.imu[0] = imuEntry(EventSource::kAccelerometer, counter_base, 0xFFFFFFFF, {-32768, 32767, 0});
  packet.imu[1] = imuEntry(EventSource::kGyroscope, counter_base, 0, {32767, -32768, -1});
  packet.imu[2] = imuEntry(EventSource::kAccelerometer, (counter_base + 1) % 4096, 123456789, {0x7FF0, -16, 15});
  packet.imu[3] = imuEntry(EventSource::kGyroscope, (counter_base + 1) % 4096, 2147483648u, {100, -200, 300});
  const std::array<EventSource, kTimestampSlotCount> sources{
      EventSource::kDepthFrame, EventSource::kFisheyeFrame, EventSource::kGpio0,        EventSource::kGpio1,
      EventSource::kGpio2,      EventSource::kDepthFrame,   EventSource::kFisheyeFrame, EventSource::kGpio0};
  for (std::size_t slot = 0; slot < kTimestampSlotCount; ++slot) {
    const std::uint16_t counter = static_cast<std::uint16_t>((counter_base + slot / 5 + 4090) % 4096);
    packet.timestamps[slot] = timestampEntry(sources[slot], counter, static_cast<std::uint32_t>(slot * 0x11111111u));
  }
  packet.timestamps[3].valid = false;  // kept: the bit is not checked on timestamp entries
  return packet;
}

void expectSameImu(const ImuEntry& a, const ImuEntry& b) {
  EXPECT_EQ(a.source, b.source);
  EXPECT_EQ(a.sample_counter, b.sample_counter);
  EXPECT_EQ(a.valid, b.valid);
  EXPECT_EQ(a.ticks, b.ticks);
  EXPECT_EQ(a.raw_xyz, b.raw_xyz);
}

void expectSameTimestamp(const TimestampEntry& a, const TimestampEntry& b) {
  EXPECT_EQ(a.source, b.source);
  EXPECT_EQ(a.frame_counter, b.frame_counter);
  EXPECT_EQ(a.valid, b.valid);
  EXPECT_EQ(a.ticks, b.ticks);
}

TEST(PacketParser, EveryFieldRoundTripsThroughTheEncoder) {
  // Counters 4094/4095 then 0/1: progress across the 12-bit wrap; the CX3 counter wraps 15 → 0.
  std::array<MotionPacket, 2> sent{fullPacket(4094), fullPacket(0)};
  sent[1].header.cx3_packet_counter = 0;
  sent[1].header.power_mode_change_done = false;

  PacketParser parser;
  ParsedTransfer out;
  ASSERT_EQ(parser.parse(encode(sent), out), 0u) << text(out.firstProblem());
  ASSERT_EQ(out.headers().size(), 2u);
  ASSERT_EQ(out.imuEntries().size(), 8u);
  ASSERT_EQ(out.timestampEntries().size(), 16u);
  for (std::size_t p = 0; p < 2; ++p) {
    const PacketHeader& header = out.headers()[p];
    EXPECT_EQ(header.error_bitmask, 0);
    EXPECT_EQ(header.power_mode_change_done, sent[p].header.power_mode_change_done);
    EXPECT_EQ(header.cx3_packet_counter, sent[p].header.cx3_packet_counter);
    EXPECT_EQ(header.imu_entry_count, 4);
    EXPECT_EQ(header.timestamp_entry_count, 8);
    for (std::size_t slot = 0; slot < kImuSlotCount; ++slot) {
      expectSameImu(out.imuEntries()[p * kImuSlotCount + slot], sent[p].imu[slot]);
    }
    for (std::size_t slot = 0; slot < kTimestampSlotCount; ++slot) {
      expectSameTimestamp(out.timestampEntries()[p * kTimestampSlotCount + slot], sent[p].timestamps[slot]);
    }
  }
  EXPECT_EQ(parser.stats().packets_accepted, 2u);
  EXPECT_EQ(parser.stats().imu_entries, 8u);
  EXPECT_EQ(parser.stats().timestamp_entries, 16u);
  EXPECT_EQ(parser.stats().cx3_counter_skips, 0u);
  EXPECT_EQ(parser.stats().totalDrops(), 0u);
}

TEST(PacketParser, UnusedSlotsAreIgnoredWhateverTheyHold) {
  MotionPacket packet = accelGyroPacket(7);
  packet.imu[2].source = static_cast<EventSource>(0);  // garbage beyond imu_entry_count = 2
  packet.imu[3].valid = false;
  PacketParser parser;
  ParsedTransfer out;
  EXPECT_EQ(parser.parse(encode(packet), out), 0u);
  EXPECT_EQ(out.imuEntries().size(), 2u);
  EXPECT_EQ(out.timestampEntries().size(), 0u);
}

TEST(PacketParser, FullTransferOfNinePacketsAndEmptyTransfers) {
  std::vector<MotionPacket> packets;
  for (std::uint16_t i = 0; i < kMaxPacketsPerTransfer; ++i) packets.push_back(accelGyroPacket(i, i % 16));
  PacketParser parser;
  ParsedTransfer out;
  EXPECT_EQ(parser.parse(encode(packets), out), 0u);
  EXPECT_EQ(out.headers().size(), 9u);
  EXPECT_EQ(out.imuEntries().size(), 18u);
  EXPECT_EQ(out.imuEntries()[17].sample_counter, 8);
  EXPECT_EQ(parser.parse({}, out), 0u);
  EXPECT_EQ(out.imuEntries().size(), 0u);
  EXPECT_EQ(parser.stats().transfers, 2u);
  EXPECT_EQ(parser.stats().empty_transfers, 1u);
}

TEST(PacketParser, EachErrorFlagDropsThePacketAndTheRestOfTheTransferByName) {
  for (std::size_t bit = 0; bit < kErrorFlagCount; ++bit) {
    std::array<MotionPacket, 3> packets{accelGyroPacket(1), accelGyroPacket(2), accelGyroPacket(3)};
    packets[1].header.error_bitmask = static_cast<std::uint16_t>(1u << bit);
    PacketParser parser;
    ParsedTransfer out;
    EXPECT_EQ(parser.parse(encode(packets), out), 1u);
    EXPECT_EQ(out.headers().size(), 1u) << "only the packet before the error is kept";
    EXPECT_EQ(parser.stats().errorFlagCount(static_cast<ErrorFlag>(bit)), 1u);
    EXPECT_EQ(parser.stats().dropCount(PacketDropReason::kDeviceError), 1u);
    EXPECT_EQ(parser.stats().dropCount(PacketDropReason::kAfterDeviceError), 1u);
    const std::string message = text(out.firstProblem());
    EXPECT_NE(message.find("packet 1 header error_bitmask"), std::string::npos) << message;
    EXPECT_NE(message.find(errorFlagName(static_cast<ErrorFlag>(bit))), std::string::npos) << message;
    EXPECT_NE(message.find("the 1 after it"), std::string::npos) << message;
  }
}

TEST(PacketParser, SeveralErrorFlagsAreAllNamed) {
  MotionPacket packet = accelGyroPacket(1);
  packet.header.error_bitmask = (1u << 3) | (1u << 5) | (1u << 11);
  PacketParser parser;
  ParsedTransfer out;
  parser.parse(encode(packet), out);
  EXPECT_EQ(text(out.firstProblem()),
            "packet 0 header error_bitmask 0x0828 (imu_fifo_overflow, crc_error, cx3_fifo_overflow): packet and the 0 "
            "after it in this transfer dropped");
  EXPECT_EQ(parser.stats().errorFlagCount(ErrorFlag::kCrcError), 1u);
  EXPECT_EQ(parser.stats().errorFlagCount(ErrorFlag::kImuNotResponding), 0u);
}

TEST(PacketParser, ShortAndPartialTransfers) {
  const std::vector<std::uint8_t> two = encode(std::array{accelGyroPacket(1), accelGyroPacket(2)});
  PacketParser parser;
  ParsedTransfer out;

  EXPECT_EQ(parser.parse(std::span(two).first(50), out), 1u);
  EXPECT_EQ(out.headers().size(), 0u);
  EXPECT_EQ(text(out.firstProblem()), "transfer of 50 B is shorter than one 104-byte packet: transfer dropped");

  EXPECT_EQ(parser.parse(std::span(two).first(104 + 20), out), 1u);
  EXPECT_EQ(out.headers().size(), 1u) << "the whole packet is kept";
  EXPECT_EQ(text(out.firstProblem()),
            "transfer of 124 B is not a whole number of 104-byte packets: trailing 20 B dropped");
  EXPECT_EQ(parser.stats().dropCount(PacketDropReason::kShortTransfer), 1u);
  EXPECT_EQ(parser.stats().dropCount(PacketDropReason::kPartialPacket), 1u);
}

TEST(PacketParser, CountsAboveTheSlotCountsDropThePacket) {
  std::array<MotionPacket, 3> packets{accelGyroPacket(1), accelGyroPacket(2), accelGyroPacket(3)};
  packets[0].header.imu_entry_count = 5;
  packets[1].header.timestamp_entry_count = 0xFFFF;
  PacketParser parser;
  ParsedTransfer out;
  EXPECT_EQ(parser.parse(encode(packets), out), 2u);
  ASSERT_EQ(out.headers().size(), 1u) << "the third packet is fine";
  EXPECT_EQ(out.imuEntries()[0].sample_counter, 3);
  EXPECT_EQ(text(out.firstProblem()), "packet 0 header imu_entry_count 5 is above the maximum 4: packet dropped");
  EXPECT_EQ(text(parser.lastProblem()),
            "packet 1 header timestamp_entry_count 65535 is above the maximum 8: packet dropped");
  EXPECT_EQ(parser.stats().dropCount(PacketDropReason::kImuCountTooLarge), 1u);
  EXPECT_EQ(parser.stats().dropCount(PacketDropReason::kTimestampCountTooLarge), 1u);
}

TEST(PacketParser, InvalidSourcesAndClearValidBitsDropTheEntry) {
  MotionPacket packet = accelGyroPacket(1);
  packet.header.imu_entry_count = 4;
  packet.imu[0].source = static_cast<EventSource>(0);
  packet.imu[2] = imuEntry(EventSource::kDepthFrame, 1, 0);  // a timestamp source in an IMU slot
  packet.imu[3] = imuEntry(EventSource::kGyroscope, 2, 0);
  packet.imu[3].valid = false;
  packet.header.timestamp_entry_count = 3;
  packet.timestamps[0] = timestampEntry(EventSource::kGyroscope, 1, 0);  // an IMU source in a timestamp slot
  packet.timestamps[1] = timestampEntry(static_cast<EventSource>(0), 1, 0);
  packet.timestamps[2] = timestampEntry(EventSource::kGpio2, 1, 0);
  PacketParser parser;
  ParsedTransfer out;
  EXPECT_EQ(parser.parse(encode(packet), out), 5u);
  ASSERT_EQ(out.imuEntries().size(), 1u);
  EXPECT_EQ(out.imuEntries()[0].source, EventSource::kGyroscope);
  ASSERT_EQ(out.timestampEntries().size(), 1u);
  EXPECT_EQ(out.timestampEntries()[0].source, EventSource::kGpio2);
  EXPECT_EQ(parser.stats().dropCount(PacketDropReason::kInvalidImuSource), 2u);
  EXPECT_EQ(parser.stats().dropCount(PacketDropReason::kImuNotValid), 1u);
  EXPECT_EQ(parser.stats().dropCount(PacketDropReason::kInvalidTimestampSource), 2u);
  EXPECT_EQ(text(out.firstProblem()),
            "packet 0 IMU slot 0 tag source code 0 is not accelerometer (1) or gyroscope (2): entry dropped");
  EXPECT_EQ(text(parser.lastProblem()),
            "packet 0 timestamp slot 1 tag source code 0 is not a frame or GPIO event (3..7): entry dropped");

  PacketProblem not_valid{.reason = PacketDropReason::kImuNotValid, .slot_index = 3, .source = EventSource::kGyroscope};
  EXPECT_EQ(text(not_valid), "packet 0 IMU slot 3 (gyroscope) tag valid bit 15 is clear: entry dropped");
}

TEST(PacketParser, CountersThatRepeatOrGoBackAreDroppedAndTheSourceReanchors) {
  PacketParser parser;
  ParsedTransfer out;
  const auto parseOne = [&](const MotionPacket& packet) { return parser.parse(encode(packet), out); };

  EXPECT_EQ(parseOne(accelGyroPacket(4094)), 0u);
  EXPECT_EQ(parseOne(accelGyroPacket(4095)), 0u);
  EXPECT_EQ(parseOne(accelGyroPacket(0)), 0u) << "4095 → 0 is the 12-bit wrap, not a step back";
  EXPECT_EQ(parseOne(accelGyroPacket(40)), 0u) << "a gap of 39 lost samples is progress";

  EXPECT_EQ(parseOne(accelGyroPacket(40)), 2u);  // accel and gyro both repeat
  EXPECT_EQ(out.imuEntries().size(), 0u);
  EXPECT_EQ(text(out.firstProblem()),
            "packet 0 IMU slot 0 accelerometer sample_counter 40 repeats the previous one: entry dropped");

  EXPECT_EQ(parseOne(accelGyroPacket(30)), 2u);
  EXPECT_EQ(text(parser.lastProblem()),
            "packet 0 IMU slot 1 gyroscope sample_counter went back from 40 to 30 (12-bit): entry dropped");
  EXPECT_EQ(parseOne(accelGyroPacket(31)), 0u) << "re-anchored on 30, so 31 is progress";
  // Half a period forward (2048) is the first step counted as going back.
  EXPECT_EQ(parseOne(accelGyroPacket(31 + 2047)), 0u);
  EXPECT_EQ(parseOne(accelGyroPacket((31 + 2047 + 2048) % 4096)), 2u);
  EXPECT_EQ(parser.stats().dropCount(PacketDropReason::kCounterRepeated), 2u);
  EXPECT_EQ(parser.stats().dropCount(PacketDropReason::kCounterWentBack), 4u);

  // Timestamp sources keep their own counters.
  MotionPacket frames;
  frames.header.timestamp_entry_count = 2;
  frames.timestamps[0] = timestampEntry(EventSource::kDepthFrame, 10, 0);
  frames.timestamps[1] = timestampEntry(EventSource::kDepthFrame, 9, 0);
  EXPECT_EQ(parseOne(frames), 1u);
  EXPECT_EQ(text(out.firstProblem()),
            "packet 0 timestamp slot 1 depth_frame frame_counter went back from 10 to 9 (12-bit): entry dropped");

  parser.reset();
  EXPECT_EQ(parseOne(accelGyroPacket(5)), 0u) << "reset forgets the counters";
  EXPECT_EQ(parser.stats().totalDrops(), 0u);
}

TEST(PacketParser, OutputTooSmallDropsTheRestOfTheTransfer) {
  const std::vector<std::uint8_t> bytes =
      encode(std::array{accelGyroPacket(1), accelGyroPacket(2), accelGyroPacket(3)});
  PacketParser parser;
  ParsedTransfer out(2);
  EXPECT_EQ(parser.parse(bytes, out), 1u);
  EXPECT_EQ(out.headers().size(), 2u);
  EXPECT_EQ(text(out.firstProblem()),
            "packet 2 does not fit the output storage of 2 packets: it and the rest of the transfer dropped");
  EXPECT_EQ(parser.stats().dropCount(PacketDropReason::kOutputFull), 1u);
}

TEST(PacketParser, Cx3CounterSkipsAreCountedNotDropped) {
  PacketParser parser;
  ParsedTransfer out;
  const std::array<std::uint8_t, 5> cx3{14, 15, 0, 2, 3};  // one skip: 0 → 2
  for (std::size_t i = 0; i < cx3.size(); ++i) {
    EXPECT_EQ(parser.parse(encode(accelGyroPacket(static_cast<std::uint16_t>(i), cx3[i])), out), 0u);
  }
  EXPECT_EQ(parser.stats().cx3_counter_skips, 1u);
  EXPECT_EQ(parser.stats().packets_accepted, 5u);
}

TEST(PacketParser, RandomBytesNeverCrashAndKeepTheBooksBalanced) {
  std::mt19937 rng(17);
  std::uniform_int_distribution<int> byte(0, 255);
  std::uniform_int_distribution<std::size_t> length(0, kMaxTransferBytes + 100);
  PacketParser parser;
  ParsedTransfer out;
  std::vector<std::uint8_t> bytes;
  for (int trial = 0; trial < 3000; ++trial) {
    bytes.resize(length(rng));
    for (auto& b : bytes) b = static_cast<std::uint8_t>(byte(rng));
    // Half the trials get a clean header in every packet, so slots are reached too.
    if (trial % 2 == 0) {
      for (std::size_t p = 0; p + kPacketBytes <= bytes.size(); p += kPacketBytes) {
        std::fill(bytes.begin() + static_cast<std::ptrdiff_t>(p), bytes.begin() + static_cast<std::ptrdiff_t>(p) + 8,
                  0);
        bytes[p + kImuEntryCountOffset] = static_cast<std::uint8_t>(trial % 5);
        bytes[p + kTimestampEntryCountOffset] = static_cast<std::uint8_t>(trial % 9);
      }
    }
    parser.parse(bytes, out);
    EXPECT_LE(out.headers().size(), bytes.size() / kPacketBytes);
    EXPECT_LE(out.imuEntries().size(), out.headers().size() * kImuSlotCount);
    EXPECT_FALSE(describe(out.firstProblem()).view().empty());
  }
  const PacketParserStats& stats = parser.stats();
  EXPECT_EQ(stats.transfers, 3000u);
  EXPECT_GT(stats.imu_entries, 0u);
  EXPECT_GT(stats.dropCount(PacketDropReason::kDeviceError), 0u);
  EXPECT_GT(stats.dropCount(PacketDropReason::kInvalidImuSource), 0u);
  EXPECT_GT(stats.dropCount(PacketDropReason::kCounterWentBack), 0u);
}

TEST(PacketParser, ParsingAndDescribingAllocateNothing) {
  std::vector<MotionPacket> packets;
  for (std::uint16_t i = 0; i < kMaxPacketsPerTransfer; ++i) packets.push_back(fullPacket(i * 2));
  packets[4].header.imu_entry_count = 9;
  std::vector<std::uint8_t> bytes = encode(packets);
  PacketParser parser;
  ParsedTransfer out;
  const std::uint64_t before = vifusion::test::heapAllocationCount();
  std::size_t problems = 0;
  for (int round = 0; round < 100; ++round) {
    problems += parser.parse(bytes, out);
    problems += describe(out.firstProblem()).view().size() > 0 ? 0 : 1;
  }
  EXPECT_EQ(vifusion::test::heapAllocationCount() - before, 0u);
  EXPECT_GT(problems, 0u);
}

}  // namespace
}  // namespace vifusion::motion
