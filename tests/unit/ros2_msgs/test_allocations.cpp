// The per-message path allocates nothing: a 640×480 depth image and an IMU sample serialised into buffers
// sized once, and read back, with operator new counted over the whole loop.

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "vifusion/core/time.hpp"
#include "vifusion/ros2_msgs/message_io.hpp"
#include "vifusion/ros2_msgs/sensor_msgs.hpp"
#include "vifusion/ros2_msgs/vifusion_msgs.hpp"
#include "vifusion/test/counting_allocations.hpp"

namespace vifusion::ros2_msgs {
namespace {

constexpr std::uint32_t kWidth = 640;
constexpr std::uint32_t kHeight = 480;
constexpr int kMessages = 30;  // one second of frames
constexpr std::int64_t kFramePeriodNs = 33'333'333;

TEST(Allocations, SerialisingAndReadingImagesAndImuAllocatesNothing) {
  // Set-up may allocate: pixels, buffers sized from a first message.
  std::vector<std::uint8_t> pixels(kWidth * kHeight * sizeof(std::uint16_t), 0x5a);
  ImageView depth;
  depth.width = kWidth;
  depth.height = kHeight;
  depth.encoding = image_encodings::kDepth16;
  depth.step = kWidth * sizeof(std::uint16_t);
  depth.data = pixels;
  depth.header = makeHeader(0, "depth");
  Imu imu;
  imu.header = makeHeader(0, "imu");
  FrameStamps stamps;
  stamps.header = depth.header;
  std::vector<std::uint8_t> image_buffer(serializedSize(depth));
  std::vector<std::uint8_t> imu_buffer(serializedSize(imu));
  std::vector<std::uint8_t> stamps_buffer(serializedSize(stamps));

  std::uint64_t pixel_bytes_read = 0;
  double gyro_sum = 0.0;
  const std::uint64_t before = test::heapAllocationCount();
  for (int i = 0; i < kMessages; ++i) {
    const std::int64_t t_ns = i * kFramePeriodNs;
    depth.header = makeHeader(t_ns, "depth");
    imu.header = makeHeader(t_ns, "imu");
    imu.angular_velocity.x = 0.001 * i;
    stamps.header = depth.header;
    stamps.index = i;
    ASSERT_TRUE(serializeMessage(depth, image_buffer).ok());
    ASSERT_TRUE(serializeMessage(imu, imu_buffer).ok());
    ASSERT_TRUE(serializeMessage(stamps, stamps_buffer).ok());
    const ImageView depth_back = deserializeMessage<ImageView>(image_buffer);
    const Imu imu_back = deserializeMessage<Imu>(imu_buffer);
    const FrameStamps stamps_back = deserializeMessage<FrameStamps>(stamps_buffer);
    pixel_bytes_read += depth_back.data.size();
    gyro_sum += imu_back.angular_velocity.x;
    ASSERT_EQ(stamps_back.index, i);
  }
  const std::uint64_t allocations = test::heapAllocationCount() - before;
  EXPECT_EQ(allocations, 0u);
  EXPECT_EQ(pixel_bytes_read, std::uint64_t{kMessages} * kWidth * kHeight * 2);
  EXPECT_NEAR(gyro_sum, 0.001 * (kMessages - 1) * kMessages / 2, 1e-12);
  EXPECT_EQ(image_buffer.size(), 4u + 8u + 10u + 2u + 8u + 10u + 1u + 1u + 4u + 4u + kWidth * kHeight * 2);
}

}  // namespace
}  // namespace vifusion::ros2_msgs
