// CdrReader on bad bytes: every problem is a vifusion::Error that names the message type, the field path
// and the byte offset; nothing reads past the input, nothing crashes.

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "sample_messages.hpp"
#include "vifusion/ros2_msgs/message_io.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion::ros2_msgs {
namespace {

using vifusion::test::expectError;

template <typename Message>
std::vector<std::uint8_t> serialized(const Message& message) {
  std::vector<std::uint8_t> buffer(serializedSize(message));
  EXPECT_TRUE(serializeMessage(message, buffer).ok());
  return buffer;
}

void patchUint32(std::vector<std::uint8_t>& bytes, std::size_t offset, std::uint32_t value) {
  std::memcpy(bytes.data() + offset, &value, sizeof(value));
}

TEST(CdrReader, TruncatedImuNamesTheFieldAndWhereItNeededBytes) {
  const test::SampleMessages samples;
  std::vector<std::uint8_t> bytes = serialized(samples.imu);
  bytes.resize(100);
  // frame "imu": orientation at 20..51, orientation_covariance at 52..123, cut at 100.
  expectError([&] { deserializeMessage<Imu>(bytes); },
              "sensor_msgs/msg/Imu field orientation_covariance at byte 52: truncated: the float64 array needs 72 "
              "bytes but the message ends at byte 100");
}

TEST(CdrReader, TruncatedNestedFieldIsNamedByItsPath) {
  const test::SampleMessages samples;
  TfMessage one;
  one.add(samples.transform);
  std::vector<std::uint8_t> bytes = serialized(one);
  // count 4..7; transforms[0]: stamp 8..15, frame_id "imu" 16..23, child "depth" 24..33, 2 padding bytes,
  // then 7 float64 from 36 (8-aligned from the header's end): rotation.z at 76..83. A cut at 80 leaves 72
  // bytes after the count, enough for the count check (72 per transform at least), not for rotation.z.
  ASSERT_EQ(bytes.size(), 92u);
  bytes.resize(80);
  expectError([&] { deserializeMessage<TfMessage>(bytes); },
              "tf2_msgs/msg/TFMessage field transforms[0].transform.rotation.z at byte 76: truncated: the float64 "
              "needs 8 bytes but the message ends at byte 80");
}

TEST(CdrReader, SequenceCountThatCannotFitIsRefusedBeforeAnyElementIsRead) {
  const test::SampleMessages samples;
  std::vector<std::uint8_t> bytes = serialized(samples.tf_static);
  bytes.resize(40);
  expectError([&] { deserializeMessage<TfMessage>(bytes); },
              "tf2_msgs/msg/TFMessage field transforms at byte 4: sequence count 3 × 72 bytes runs past the end of "
              "the message (40 bytes, 32 left)");
}

TEST(CdrReader, HugeSequenceCountIsAnErrorNotAnAllocation) {
  const test::SampleMessages samples;
  std::vector<std::uint8_t> bytes = serialized(samples.depth);
  // stamp 4..11, "depth" 12..21, pad, height 24, width 28, "16UC1" 32..41, is_bigendian 42, pad, step 44,
  // data count 48, pixels 52..81.
  patchUint32(bytes, 48, 0xffffffffu);
  expectError([&] { deserializeMessage<ImageView>(bytes); },
              "sensor_msgs/msg/Image field data at byte 48: sequence count 4294967295 × 1 bytes runs past the end "
              "of the message (82 bytes, 30 left)");
}

TEST(CdrReader, TransformCountOverTheCapacityIsRefusedByName) {
  // 17 all-zero transforms are valid CDR (zero-length strings, zero numbers), so only the capacity stops them.
  std::vector<std::uint8_t> bytes(4 + 4 + 17 * 80, 0);
  std::memcpy(bytes.data(), kCdrLittleEndianHeader.data(), kCdrLittleEndianHeader.size());
  patchUint32(bytes, 4, 17);
  expectError([&] { deserializeMessage<TfMessage>(bytes); },
              "tf2_msgs/msg/TFMessage field transforms at byte 4: sequence count 17 exceeds the capacity of 16");
}

TEST(CdrReader, StringLengthPastTheEndIsNamed) {
  const test::SampleMessages samples;
  std::vector<std::uint8_t> bytes = serialized(samples.header);
  patchUint32(bytes, 12, 1'000'000);
  expectError([&] { deserializeMessage<Header>(bytes); },
              "std_msgs/msg/Header field frame_id at byte 12: string length 1000000 runs past the end of the message "
              "(43 bytes, 27 left)");
}

TEST(CdrReader, StringWithoutItsNulIsRefused) {
  const test::SampleMessages samples;
  std::vector<std::uint8_t> bytes = serialized(samples.header);
  bytes.back() = 'x';  // the NUL of "camera_depth_optical_frame"
  expectError([&] { deserializeMessage<Header>(bytes); },
              "field frame_id at byte 12: string of length 27 does not "
              "end in a NUL byte");
}

// Found by fuzz_cdr_messages: such a string was accepted, and our writer refused to write it back.
TEST(CdrReader, StringWithANulBeforeItsEndIsRefused) {
  const test::SampleMessages samples;
  std::vector<std::uint8_t> bytes = serialized(samples.header);
  bytes[16 + 6] = '\0';  // "camera_depth_optical_frame" starts at byte 16 (after its length)
  expectError([&] { deserializeMessage<Header>(bytes); },
              "std_msgs/msg/Header field frame_id at byte 12: string of length 27 holds a NUL byte at index 6, "
              "before its end");
}

TEST(CdrReader, BoolOtherThanZeroOrOneIsRefused) {
  const test::SampleMessages samples;
  std::vector<std::uint8_t> bytes = serialized(samples.sync_edge);
  // stamp 4..11, "sync" 12..20, rising at 21.
  ASSERT_EQ(bytes[21], 0);
  bytes[21] = 7;
  expectError([&] { deserializeMessage<SyncEdge>(bytes); },
              "vifusion_msgs/msg/SyncEdge field rising at byte 21: bool byte is 7, not 0 or 1");
}

TEST(CdrReader, NanosecondsOfOneSecondOrMoreAreRefused) {
  std::vector<std::uint8_t> bytes = serialized(Time{5, 0});
  patchUint32(bytes, 8, 1'000'000'000);
  expectError([&] { deserializeMessage<Time>(bytes); },
              "builtin_interfaces/msg/Time field nanosec at byte 8: 1000000000 ns is not below one second");
  const test::SampleMessages samples;
  bytes = serialized(samples.imu);
  patchUint32(bytes, 8, 4'000'000'000u);
  expectError([&] { deserializeMessage<Imu>(bytes); }, "sensor_msgs/msg/Imu field header.stamp.nanosec at byte 8");
}

TEST(CdrReader, UnknownClockStateIsRefused) {
  const test::SampleMessages samples;
  std::vector<std::uint8_t> bytes = serialized(samples.clock_mapping);
  // stamp 4..11, "" 12..16, "zr300_motion" length 17..19 pad, 20..23, chars 24..36, state at 37.
  ASSERT_EQ(bytes[37], 1);
  bytes[37] = 3;
  expectError([&] { deserializeMessage<ClockMapping>(bytes); },
              "vifusion_msgs/msg/ClockMapping field state at byte 37: 3 is none of STATE_EMPTY");
}

TEST(CdrReader, ImageDataOfTheWrongSizeIsRefused) {
  const test::SampleMessages samples;
  std::vector<std::uint8_t> bytes = serialized(samples.depth);
  patchUint32(bytes, 44, 11);  // step 10 → 11: 33 bytes expected, 30 present
  expectError([&] { deserializeMessage<ImageView>(bytes); },
              "sensor_msgs/msg/Image field data at byte 48: holds 30 bytes, not step × height = 11 × 3 = 33");
}

TEST(CdrReader, EncapsulationOtherThanCdrLeIsRefused) {
  const std::vector<std::uint8_t> big_endian{0x00, 0x00, 0x00, 0x00, 0, 0, 0, 5, 0, 0, 0, 0};
  expectError([&] { deserializeMessage<Time>(big_endian); },
              "builtin_interfaces/msg/Time field encapsulation header at byte 0: encapsulation 00 00 is not read");
  const std::vector<std::uint8_t> xcdr2{0x00, 0x07, 0x00, 0x00, 5, 0, 0, 0, 0, 0, 0, 0};
  expectError([&] { deserializeMessage<Time>(xcdr2); }, "encapsulation 00 07 is not read");
  const std::vector<std::uint8_t> too_short{0x00, 0x01};
  expectError([&] { deserializeMessage<Time>(too_short); },
              "the message is 2 bytes, shorter than the 4-byte encapsulation header");
}

/// Every cut of a valid message is a vifusion::Error, never a crash or a read past the end.
template <typename Message>
void expectEveryTruncationFails(const Message& message) {
  const std::vector<std::uint8_t> bytes = serialized(message);
  for (std::size_t length = 0; length < bytes.size(); ++length) {
    // A copy of exactly `length` bytes, so that a read past its end is caught by sanitizers too.
    const std::vector<std::uint8_t> cut(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(length));
    EXPECT_THROW(deserializeMessage<Message>(cut), Error) << Message::kTypeName << " cut to " << length;
  }
}

TEST(CdrReader, EveryTruncationOfEveryTypeIsAnError) {
  const test::SampleMessages samples;
  expectEveryTruncationFails(samples.header);
  expectEveryTruncationFails(samples.depth);
  expectEveryTruncationFails(samples.imu);
  expectEveryTruncationFails(samples.camera_info_plumb_bob);
  expectEveryTruncationFails(samples.tf_static);
  expectEveryTruncationFails(samples.frame_stamps);
  expectEveryTruncationFails(samples.motion_packet);
  expectEveryTruncationFails(samples.sync_edge);
  expectEveryTruncationFails(samples.clock_mapping);
  expectEveryTruncationFails(samples.recording_info);
}

/// Random byte corruption either still decodes or throws vifusion::Error; any other outcome fails.
template <typename Message>
int decodeCorrupted(const Message& message, std::mt19937& random, int trials) {
  const std::vector<std::uint8_t> original = serialized(message);
  std::uniform_int_distribution<std::size_t> position(0, original.size() - 1);
  std::uniform_int_distribution<int> value(0, 255);
  int errors = 0;
  for (int trial = 0; trial < trials; ++trial) {
    std::vector<std::uint8_t> bytes = original;
    for (int flip = 0; flip < 3; ++flip) bytes[position(random)] = static_cast<std::uint8_t>(value(random));
    try {
      (void)deserializeMessage<Message>(bytes);
    } catch (const Error&) {
      ++errors;
    }
  }
  return errors;
}

TEST(CdrReader, CorruptedBytesDecodeOrThrowOnlyVifusionErrors) {
  const test::SampleMessages samples;
  std::mt19937 random(18);
  constexpr int kTrials = 2000;
  // Each type sees some errors (lengths, counts, bools hit) and no other exception escapes.
  EXPECT_GT(decodeCorrupted(samples.tf_static, random, kTrials), 0);
  EXPECT_GT(decodeCorrupted(samples.camera_info_plumb_bob, random, kTrials), 0);
  EXPECT_GT(decodeCorrupted(samples.recording_info, random, kTrials), 0);
  EXPECT_GT(decodeCorrupted(samples.depth, random, kTrials), 0);
}

}  // namespace
}  // namespace vifusion::ros2_msgs
