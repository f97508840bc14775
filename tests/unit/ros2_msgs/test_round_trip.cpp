// Every message type written and read back gives the values it started with; strings and pixel data come
// back as views into the serialised bytes, not copies.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "sample_messages.hpp"
#include "vifusion/ros2_msgs/message_io.hpp"

namespace vifusion::ros2_msgs {
namespace {

template <typename Message>
std::vector<std::uint8_t> serialized(const Message& message) {
  std::vector<std::uint8_t> buffer(serializedSize(message));
  const CdrWriter writer = serializeMessage(message, buffer);
  EXPECT_TRUE(writer.ok()) << Message::kTypeName << ": " << writer.failure();
  return buffer;
}

template <typename Message>
Message roundTrip(const Message& message, std::vector<std::uint8_t>& storage) {
  storage = serialized(message);
  return deserializeMessage<Message>(storage);
}

template <typename Message>
void expectRoundTrip(const Message& message) {
  std::vector<std::uint8_t> storage;
  EXPECT_EQ(roundTrip(message, storage), message) << Message::kTypeName;
}

bool pointsInto(const void* pointer, const std::vector<std::uint8_t>& storage) {
  const auto* byte = static_cast<const std::uint8_t*>(pointer);
  return byte >= storage.data() && byte < storage.data() + storage.size();
}

TEST(RoundTrip, PlainTypesComeBackEqual) {
  const test::SampleMessages samples;
  expectRoundTrip(samples.time);
  expectRoundTrip(samples.header);
  expectRoundTrip(samples.imu);
  expectRoundTrip(samples.camera_info_plumb_bob);
  expectRoundTrip(samples.camera_info_equidistant);
  expectRoundTrip(samples.transform);
  expectRoundTrip(samples.tf_static);
  expectRoundTrip(samples.frame_stamps);
  expectRoundTrip(samples.sync_edge);
  expectRoundTrip(samples.clock_mapping);
  expectRoundTrip(samples.recording_info);
  expectRoundTrip(RegionOfInterest{1, 2, 3, 4, true});
  expectRoundTrip(Vector3{1.5, -2.5, 3.25});
  expectRoundTrip(Quaternion{0.1, 0.2, 0.3, 0.9});
  expectRoundTrip(Transform{Vector3{1, 2, 3}, Quaternion{0, 0, 1, 0}});
}

TEST(RoundTrip, ValuesSurviveExactly) {
  const test::SampleMessages samples;
  std::vector<std::uint8_t> storage;
  const Imu imu = roundTrip(samples.imu, storage);
  EXPECT_EQ(imu.header.stamp.sec, 1'234);
  EXPECT_EQ(imu.header.stamp.nanosec, 572'890'123u);
  EXPECT_EQ(imu.header.frame_id, "imu");
  EXPECT_EQ(imu.orientation_covariance[0], -1.0);  // no orientation estimate
  EXPECT_EQ(imu.angular_velocity.y, -0.25);
  EXPECT_EQ(imu.linear_acceleration.y, 9.7921);
  EXPECT_EQ(imu.linear_acceleration_covariance[8], 1.5e-2);
  EXPECT_TRUE(pointsInto(imu.header.frame_id.data(), storage));

  const SyncEdge edge = roundTrip(samples.sync_edge, storage);
  EXPECT_EQ(edge.sequence, 0x1234'5678'9abc'def0ull);
  EXPECT_FALSE(edge.rising);

  const ClockMapping mapping = roundTrip(samples.clock_mapping, storage);
  EXPECT_EQ(mapping.state, ClockMappingState::kWarmingUp);
  EXPECT_EQ(mapping.offset_ns, 1'234'567'890'123 + 999 - 987'654'321'012);
  EXPECT_EQ(mapping.device, "zr300_motion");

  const TfMessage tf = roundTrip(samples.tf_static, storage);
  ASSERT_EQ(tf.transform_count, 3u);
  EXPECT_EQ(tf.transforms[1].child_frame_id, "colour");
  EXPECT_EQ(tf.transforms[1].transform.rotation.y, -0.5003);
  EXPECT_EQ(tf.transforms[2].header.frame_id, "base_link");

  const CameraInfo info = roundTrip(samples.camera_info_equidistant, storage);
  EXPECT_EQ(info.distortion_model, "equidistant");
  ASSERT_EQ(info.d_count, 4u);
  EXPECT_EQ(info.d[3], 0.0129);
  EXPECT_EQ(info.k[4], 277.75);
}

void expectImageRoundTrip(const ImageView& image) {
  std::vector<std::uint8_t> storage;
  const ImageView back = roundTrip(image, storage);
  EXPECT_EQ(back.header, image.header);
  EXPECT_EQ(back.height, image.height);
  EXPECT_EQ(back.width, image.width);
  EXPECT_EQ(back.encoding, image.encoding);
  EXPECT_EQ(back.is_bigendian, image.is_bigendian);
  EXPECT_EQ(back.step, image.step);
  ASSERT_EQ(back.data.size(), image.data.size());
  EXPECT_TRUE(std::ranges::equal(back.data, image.data));
  // The pixels are a view of the serialised bytes (the last data.size() bytes of the message).
  EXPECT_EQ(back.data.data(), storage.data() + storage.size() - image.data.size());
}

TEST(RoundTrip, ImagesComeBackAsViewsOfTheBytes) {
  const test::SampleMessages samples;
  expectImageRoundTrip(samples.depth);
  expectImageRoundTrip(samples.rgb);
  expectImageRoundTrip(samples.yuyv);
  EXPECT_EQ(samples.depth.step, 10u);  // 5 px × 2 bytes
  EXPECT_EQ(samples.rgb.step, 15u);    // 5 px × 3 bytes
  EXPECT_EQ(samples.yuyv.step, 10u);   // 5 px × 2 bytes (Y + alternately U or V)
}

TEST(RoundTrip, MotionPacketKeepsEveryRawByte) {
  const test::SampleMessages samples;
  std::vector<std::uint8_t> storage;
  const MotionPacket back = roundTrip(samples.motion_packet, storage);
  EXPECT_EQ(back.header, samples.motion_packet.header);
  EXPECT_EQ(back.transfer_index, 65'537u);
  ASSERT_EQ(back.data.size(), test::kSampleMotionPacketBytes);
  EXPECT_TRUE(std::ranges::equal(back.data, samples.motion_packet.data));
  EXPECT_TRUE(pointsInto(back.data.data(), storage));
}

TEST(RoundTrip, EmptyStringsAndSequencesRoundTrip) {
  TfMessage empty_tf;
  expectRoundTrip(empty_tf);
  CameraInfo no_distortion;
  expectRoundTrip(no_distortion);
  MotionPacket empty_packet;
  std::vector<std::uint8_t> storage;
  EXPECT_TRUE(roundTrip(empty_packet, storage).data.empty());
}

}  // namespace
}  // namespace vifusion::ros2_msgs
