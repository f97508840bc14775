// CdrWriter: never writes past the caller's span, reports overflow with the size the message needs, and
// refuses values CDR cannot carry.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "sample_messages.hpp"
#include "vifusion/ros2_msgs/cdr_writer.hpp"
#include "vifusion/ros2_msgs/message_io.hpp"

namespace vifusion::ros2_msgs {
namespace {

constexpr std::uint8_t kGuardByte = 0xa5;

TEST(CdrWriter, StartsWithTheLittleEndianEncapsulationHeader) {
  std::array<std::uint8_t, 8> buffer{};
  const CdrWriter writer(buffer);
  EXPECT_TRUE(writer.ok());
  EXPECT_EQ(writer.size(), 4u);
  ASSERT_EQ(writer.bytes().size(), 4u);
  EXPECT_TRUE(std::ranges::equal(writer.bytes(), kCdrLittleEndianHeader));
}

TEST(CdrWriter, OverflowStopsAtTheSpanEndAndStillCountsTheNeededSize) {
  const test::SampleMessages samples;
  const std::size_t full_size = serializedSize(samples.imu);
  ASSERT_EQ(full_size, 4u + 16u + 296u);  // frame "imu": no padding before the float64 fields

  std::vector<std::uint8_t> full(full_size);
  ASSERT_TRUE(serializeMessage(samples.imu, full).ok());

  // A 100-byte span inside a larger guarded array: nothing beyond byte 100 may change.
  std::vector<std::uint8_t> backing(full_size + 16, kGuardByte);
  const std::span<std::uint8_t> short_span(backing.data(), 100);
  const CdrWriter writer = serializeMessage(samples.imu, short_span);
  EXPECT_FALSE(writer.ok());
  EXPECT_TRUE(writer.overflowed());
  EXPECT_EQ(writer.size(), full_size);
  EXPECT_EQ(writer.capacity(), 100u);
  EXPECT_TRUE(writer.bytes().empty());
  EXPECT_NE(writer.failure().find("needs more bytes"), std::string_view::npos) << writer.failure();
  EXPECT_TRUE(std::all_of(backing.begin() + 100, backing.end(), [](std::uint8_t b) { return b == kGuardByte; }));
  // Fields are copied whole or not at all: bytes 0..51 (header, stamp, frame_id, orientation) are the
  // message's true prefix; orientation_covariance (52..123) did not fit, so 52..99 were never touched.
  EXPECT_TRUE(std::equal(backing.begin(), backing.begin() + 52, full.begin()));
  EXPECT_TRUE(std::all_of(backing.begin() + 52, backing.begin() + 100, [](std::uint8_t b) { return b == kGuardByte; }));
}

TEST(CdrWriter, EmptySpanSizesAMessage) {
  const test::SampleMessages samples;
  const CdrWriter writer = serializeMessage(samples.depth, std::span<std::uint8_t>());
  EXPECT_TRUE(writer.overflowed());
  // header 4 + stamp 8 + "depth" (4 + 6) + pad 2 + height, width 8 + "16UC1" (4 + 6) + is_bigendian 1 + pad 1
  // + step 4 + count 4 + 5 × 3 × 2 pixel bytes.
  EXPECT_EQ(writer.size(), 4u + 8u + 10u + 2u + 8u + 10u + 1u + 1u + 4u + 4u + 30u);
}

TEST(CdrWriter, ResetStartsAFreshMessageAfterAFailure) {
  std::array<std::uint8_t, 16> buffer{};
  CdrWriter writer(buffer);
  writer.writeString("far longer than sixteen bytes");
  EXPECT_FALSE(writer.ok());
  writer.reset();
  EXPECT_TRUE(writer.ok());
  writer.writeUint32(7);
  EXPECT_EQ(writer.size(), 8u);
  EXPECT_EQ(writer.bytes()[4], 7);
}

TEST(CdrWriter, RefusesAStringWithANulByte) {
  std::array<std::uint8_t, 64> buffer{};
  CdrWriter writer(buffer);
  writer.writeString(std::string_view("ab\0cd", 5));
  EXPECT_FALSE(writer.ok());
  EXPECT_FALSE(writer.overflowed());
  EXPECT_NE(writer.failure().find("NUL"), std::string_view::npos);
}

TEST(CdrWriter, RefusesAnImageWhoseDataIsNotStepTimesHeight) {
  const test::SampleMessages samples;
  ImageView image = samples.rgb;
  image.step += 1;  // 16 bytes per row × 3 rows ≠ 45 bytes of data
  std::vector<std::uint8_t> buffer(serializedSize(image));
  const CdrWriter writer = serializeMessage(image, buffer);
  EXPECT_FALSE(writer.ok());
  EXPECT_FALSE(writer.overflowed());
  EXPECT_NE(writer.failure().find("step × height"), std::string_view::npos) << writer.failure();
}

TEST(CdrWriter, RefusesMoreTransformsThanTheCapacity) {
  TfMessage message;
  message.transform_count = TfMessage::kCapacity + 1;
  std::array<std::uint8_t, 64> buffer{};
  EXPECT_FALSE(serializeMessage(message, buffer).ok());
}

TEST(CdrWriter, AddingBeyondTheCapacityChangesNothing) {
  TfMessage message;
  for (std::size_t i = 0; i < TfMessage::kCapacity; ++i) EXPECT_TRUE(message.add(TransformStamped{}));
  EXPECT_FALSE(message.add(TransformStamped{}));
  EXPECT_EQ(message.transform_count, TfMessage::kCapacity);
  CameraInfo info;
  const std::array<double, CameraInfo::kMaxDistortionCoefficients + 1> too_many{};
  EXPECT_FALSE(info.setDistortion(too_many));
  EXPECT_EQ(info.d_count, 0u);
}

TEST(CdrWriter, EmptyFloat64SequenceAddsNoPadding) {
  // Foxglove's reader and Fast-CDR align a float64 sequence only when it has elements.
  std::array<std::uint8_t, 16> buffer{};
  CdrWriter writer(buffer);
  writer.writeUint8(1);
  writer.writeFloat64Sequence({});  // pad 3 to the uint32 count, no padding for zero elements
  writer.writeUint8(2);
  EXPECT_EQ(writer.size(), 4u + 1u + 3u + 4u + 1u);
}

}  // namespace
}  // namespace vifusion::ros2_msgs
