// Byte layouts computed by hand from the CDR rules (cdr_encoding.hpp), compared with what the writer
// produces: the encapsulation header, string length with its NUL, padding after strings, and alignment
// counted from the END of the 4-byte header (so an 8-aligned float64 sits at an absolute offset ≡ 4 mod 8).

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

#include "byte_builder.hpp"
#include "vifusion/ros2_msgs/message_io.hpp"
#include "vifusion/ros2_msgs/sensor_msgs.hpp"
#include "vifusion/ros2_msgs/time_header.hpp"

namespace vifusion::ros2_msgs {
namespace {

using test::ByteBuilder;

template <typename Message>
std::vector<std::uint8_t> serialized(const Message& message) {
  std::vector<std::uint8_t> buffer(serializedSize(message));
  const CdrWriter writer = serializeMessage(message, buffer);
  EXPECT_TRUE(writer.ok()) << writer.failure();
  EXPECT_EQ(writer.size(), buffer.size());
  return buffer;
}

TEST(ByteLayout, HeaderIsStampThenLengthPrefixedNulTerminatedFrameId) {
  const Header header{Time{-2, 300'000'000}, "imu"};
  const std::vector<std::uint8_t> expected{
      0x00, 0x01, 0x00, 0x00,  // encapsulation: CDR_LE, no options
      0xfe, 0xff, 0xff, 0xff,  // stamp.sec = -2 (int32)
      0x00, 0xa3, 0xe1, 0x11,  // stamp.nanosec = 300000000 = 0x11e1a300 (uint32)
      0x04, 0x00, 0x00, 0x00,  // frame_id length 4: "imu" + NUL
      'i',  'm',  'u',  0x00,  // no padding after the last field
  };
  EXPECT_EQ(serialized(header), expected);
  EXPECT_EQ(serializedSize(header), 20u);
}

TEST(ByteLayout, ImagePadsAfterEachStringToTheNextFourByteField) {
  const std::array<std::uint8_t, 6> pixels{10, 20, 30, 40, 50, 60};
  ImageView image;
  image.header = Header{Time{1, 2}, "s"};
  image.height = 1;
  image.width = 2;
  image.encoding = "rgb8";
  image.step = 6;
  image.data = pixels;

  ByteBuilder expected;
  expected.raw({0x00, 0x01, 0x00, 0x00});         // header end = body offset 0
  expected.i32(1).u32(2);                         // body 0..7: stamp
  expected.u32(2).chars("s");                     // body 8..13: frame_id length 2, 's', NUL
  expected.zeros(2);                              // body 14, 15: pad to 16
  expected.u32(1).u32(2);                         // body 16..23: height, width
  expected.u32(5).chars("rgb8");                  // body 24..32: encoding length 5, "rgb8", NUL
  expected.u8(0);                                 // body 33: is_bigendian (uint8: no alignment)
  expected.zeros(2);                              // body 34, 35: pad to 36
  expected.u32(6);                                // body 36..39: step
  expected.u32(6).raw({10, 20, 30, 40, 50, 60});  // body 40..49: data count, bytes
  ASSERT_EQ(expected.size(), 54u);
  EXPECT_EQ(serialized(image), expected.bytes());
}

TEST(ByteLayout, ImuAlignsFloat64ToEightBytesCountedFromTheEndOfTheHeader) {
  Imu imu;
  imu.header = Header{Time{1'234, 567'890'123}, "s"};
  imu.orientation = Quaternion{0.5, -0.5, 0.25, 0.625};
  imu.orientation_covariance = {-1, 0, 0, 0, 0, 0, 0, 0, 0};
  imu.angular_velocity = Vector3{0.125, -2.5, 1e-3};
  imu.angular_velocity_covariance = {1, 2, 3, 4, 5, 6, 7, 8, 9};
  imu.linear_acceleration = Vector3{0.25, 9.81, -0.5};
  imu.linear_acceleration_covariance = {9, 8, 7, 6, 5, 4, 3, 2, 1};

  ByteBuilder expected;
  expected.raw({0x00, 0x01, 0x00, 0x00});
  expected.i32(1'234).u32(567'890'123);  // body 0..7: stamp
  expected.u32(2).chars("s");            // body 8..13: frame_id
  // body 14 → 16: the next float64 is 8-aligned from the header's end, i.e. at absolute offset 20, which
  // is NOT a multiple of 8 (aligning to the buffer start would have put it at 24).
  expected.zeros(2);
  const std::size_t orientation_offset = expected.size();
  for (double value : {0.5, -0.5, 0.25, 0.625}) expected.f64(value);            // body 16..47
  for (double value : imu.orientation_covariance) expected.f64(value);          // body 48..119
  for (double value : {0.125, -2.5, 1e-3}) expected.f64(value);                 // body 120..143
  for (double value : imu.angular_velocity_covariance) expected.f64(value);     // body 144..215
  for (double value : {0.25, 9.81, -0.5}) expected.f64(value);                  // body 216..239
  for (double value : imu.linear_acceleration_covariance) expected.f64(value);  // body 240..311

  EXPECT_EQ(orientation_offset, 20u);
  ASSERT_EQ(expected.size(), 316u);
  EXPECT_EQ(serialized(imu), expected.bytes());
}

TEST(ByteLayout, FrameIdOfFourCharactersNeedsNoPaddingBeforeFloat64) {
  // "imu1" + NUL = 5 bytes: body 12..16, next 8-aligned offset 24 → 7 padding bytes; "imu" + NUL = 4 bytes:
  // body 12..15, offset 16 is 8-aligned → none. Sizes differ by exactly those 7 + 1 bytes.
  Imu with_three;
  with_three.header.frame_id = "imu";
  Imu with_four;
  with_four.header.frame_id = "imu1";
  EXPECT_EQ(serializedSize(with_three), 4u + 16u + 296u);
  EXPECT_EQ(serializedSize(with_four), 4u + 24u + 296u);
}

}  // namespace
}  // namespace vifusion::ros2_msgs
