// The bytes vifusion puts on the wire, against XCDR1 worked out by hand: what ROS 2 (Humble, Iron)
// parses. XCDR1 rules used below (DDS-XTypes 1.3 §7.4.1, OMG CDR):
//   - a 4-byte encapsulation header: 00 01 = CDR_LE (XCDR1, little-endian), then 2 option bytes;
//   - every primitive is aligned to its own size, counted from the first byte AFTER the header,
//     so doubles sit on multiples of 8 (XCDR2 would cap alignment at 4);
//   - a string is a uint32 length that counts the terminating NUL, the characters, then the NUL;
//   - a sequence is a uint32 element count followed by the elements; final structs add nothing.
// Cyclone pads the payload to a multiple of 4 and records the number of padding bytes in the low two
// bits of the options (ddsi_cdrstream.c, dds_ostream_add_to_serdata_default).

#include <gtest/gtest.h>

#include <cstring>
#include <initializer_list>

#include "dds_test_support.hpp"
#include "sample_messages.hpp"
#include "serialised_sample.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/dds/reader.hpp"
#include "vifusion/dds/writer.hpp"

namespace vifusion::dds {
namespace {

constexpr std::int64_t kTimeoutNs = 5 * kNsPerSecond;

/// Builds expected bytes one field at a time. It never aligns by itself: every padding byte in a
/// test is written out with the offset arithmetic that requires it.
class ExpectedBytes {
 public:
  ExpectedBytes& raw(std::initializer_list<std::uint8_t> bytes) {
    bytes_.insert(bytes_.end(), bytes);
    return *this;
  }
  ExpectedBytes& zeros(std::size_t n) {
    bytes_.insert(bytes_.end(), n, 0);
    return *this;
  }
  ExpectedBytes& u8(std::uint8_t v) { return little(v); }
  ExpectedBytes& u32(std::uint32_t v) { return little(v); }
  ExpectedBytes& i32(std::int32_t v) { return little(v); }
  ExpectedBytes& f64(double v) { return little(v); }
  ExpectedBytes& string(const char* text) {
    const std::size_t n = std::strlen(text) + 1;
    u32(static_cast<std::uint32_t>(n));
    bytes_.insert(bytes_.end(), text, text + n);
    return *this;
  }
  /// Offset from the start of the payload (after the 4-byte header) [B].
  std::size_t offset() const { return bytes_.size() - 4; }
  const std::vector<std::uint8_t>& bytes() const { return bytes_; }

 private:
  template <typename T>
  ExpectedBytes& little(T v) {
    std::uint8_t b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));  // the test host is little-endian (static_assert in conversions.hpp)
    bytes_.insert(bytes_.end(), b, b + sizeof(T));
    return *this;
  }

  std::vector<std::uint8_t> bytes_;
};

template <typename Msg>
std::vector<std::uint8_t> serialised(const Topic<Msg>& topic, const Msg& message) {
  const Participant participant(test::loopbackOptions());
  const Reader<Msg> reader(participant, topic);
  Writer<Msg> writer(participant, topic);
  EXPECT_TRUE(writer.write(message));
  return test::takeSerialised(reader.reader(), kTimeoutNs);
}

msg::PoseStamped handPose() {
  // q = (0.5, 0.5, 0.5, 0.5) is a unit quaternion, so SE3d keeps it exactly.
  return makePoseStamped(1'700'000'000'123'456'789, "world",
                         SE3d(Eigen::Quaterniond(0.5, 0.5, 0.5, 0.5), Eigen::Vector3d(1.0, 2.0, -0.5)));
}

// 84 bytes, every one written out by hand.
const std::vector<std::uint8_t> kHandPoseBytes = {
    0x00, 0x01, 0x00, 0x00,                          // CDR_LE, no padding at the end
    0x00, 0xf1, 0x53, 0x65,                          //  0: header.stamp.sec = 1700000000 = 0x6553f100
    0x15, 0xcd, 0x5b, 0x07,                          //  4: header.stamp.nanosec = 123456789 = 0x075bcd15
    0x06, 0x00, 0x00, 0x00,                          //  8: frame_id length 6 ("world" + NUL)
    'w',  'o',  'r',  'l',  'd',  0x00,              // 12: frame_id
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00,              // 18: pad to 24, a multiple of 8 for the doubles
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xf0, 0x3f,  // 24: position.x = 1.0
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x40,  // 32: position.y = 2.0
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xe0, 0xbf,  // 40: position.z = -0.5
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xe0, 0x3f,  // 48: orientation.x = 0.5
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xe0, 0x3f,  // 56: orientation.y
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xe0, 0x3f,  // 64: orientation.z
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xe0, 0x3f,  // 72: orientation.w; payload ends at 80
};

TEST(DdsWireBytes, PoseStampedIsXcdr1LittleEndian) { EXPECT_EQ(serialised(topics::kPose, handPose()), kHandPoseBytes); }

TEST(DdsWireBytes, OdometryIsXcdr1LittleEndian) {
  Matrix6d pose_covariance;
  Matrix6d twist_covariance;
  for (int i = 0; i < 36; ++i) {
    pose_covariance(i / 6, i % 6) = 0.01 * i;  // row-major index i
    twist_covariance(i / 6, i % 6) = -1.0 * i;
  }
  const SE3d T_W_C(Eigen::Quaterniond(0.5, -0.5, 0.5, -0.5), Eigen::Vector3d(3.0, -4.0, 0.25));
  // v_W = R_W_C · (0.5, -1, 2) so the twist carries exactly (0.5, -1, 2) in C.
  const Eigen::Vector3d v_C(0.5, -1.0, 2.0);
  const msg::Odometry odometry = makeOdometry(-1'500'000'000, "map", "camera", T_W_C, T_W_C.rotationMatrix() * v_C,
                                              Eigen::Vector3d(0.125, 0.0, -8.0), pose_covariance, twist_covariance);
  ASSERT_EQ(odometry.twist.twist.linear.x, 0.5) << "test set-up: the rotation must be exact";

  ExpectedBytes expected;
  expected.raw({0x00, 0x01, 0x00, 0x00});  // CDR_LE; ends on a double, so no padding
  expected.i32(-2).u32(500'000'000);       //  0: stamp of −1.5 s: sec −2, nanosec 0.5e9
  expected.string("map");                  //  8: length 4 + "map\0" → 16
  expected.string("camera");               // 16: length 7 + "camera\0" → 27
  ASSERT_EQ(expected.offset(), 27u);
  expected.zeros(5);                                    // 27 → 32 for pose.pose.position.x
  expected.f64(3.0).f64(-4.0).f64(0.25);                // 32: position
  expected.f64(-0.5).f64(0.5).f64(-0.5).f64(0.5);       // 56: orientation x, y, z, w (w > 0 kept by SE3d)
  for (int i = 0; i < 36; ++i) expected.f64(0.01 * i);  // 88: pose.covariance, row-major
  ASSERT_EQ(expected.offset(), 376u);
  expected.f64(0.5).f64(-1.0).f64(2.0);                 // 376: twist.linear in C
  expected.f64(0.125).f64(0.0).f64(-8.0);               // 400: twist.angular
  for (int i = 0; i < 36; ++i) expected.f64(-1.0 * i);  // 424: twist.covariance → 712
  ASSERT_EQ(expected.offset(), 712u);

  EXPECT_EQ(serialised(topics::kOdometry, odometry), expected.bytes());
}

TEST(DdsWireBytes, ImuStateIsXcdr1LittleEndian) {
  // vifusion_msgs/ImuState as a ROS 2 vifusion_msgs package with the same fields would parse it: I = W
  // keeps every value exact; the gravity direction is held (gyro mode), so its variances are −1.
  NavState x;
  x.v_I_S = Eigen::Vector3d(0.5, -0.25, 2.0);
  x.b_g = Eigen::Vector3d(0.125, 0.0, -0.0625);
  x.b_a = Eigen::Vector3d(-1.5, 0.75, 4.0);
  Vector18d variance = Vector18d::Zero();
  variance.segment<3>(kIdxV) << 0.25, 0.5, 1.0;
  variance.segment<3>(kIdxBg) << 1.0 / 1024, 2.0 / 1024, 3.0 / 1024;
  variance.segment<3>(kIdxBa) << 8.0, 16.0, 32.0;
  const msg::ImuState state = makeImuStateFromVariances(3 * kNsPerSecond + 250, "map", x, variance);

  ExpectedBytes expected;
  expected.raw({0x00, 0x01, 0x00, 0x00});     // CDR_LE; ends on a double, so no padding
  expected.i32(3).u32(250);                   //  0: stamp
  expected.string("map");                     //  8: length 4 + "map\0" → 16, already a multiple of 8
  expected.f64(0.5).f64(-0.25).f64(2.0);      // 16: velocity in W
  expected.f64(0.125).f64(0.0).f64(-0.0625);  // 40: gyro_bias
  expected.f64(-1.5).f64(0.75).f64(4.0);      // 64: accel_bias
  expected.f64(0.0).f64(0.0).f64(-1.0);       // 88: gravity_direction in W
  ASSERT_EQ(expected.offset(), 112u);
  expected.f64(0.25).f64(0.5).f64(1.0);                      // 112: velocity_covariance
  expected.f64(1.0 / 1024).f64(2.0 / 1024).f64(3.0 / 1024);  // 136: gyro_bias_covariance
  expected.f64(8.0).f64(16.0).f64(32.0);                     // 160: accel_bias_covariance
  expected.f64(-1.0).f64(-1.0).f64(-1.0);                    // 184: gravity_direction_covariance: held
  ASSERT_EQ(expected.offset(), 208u);

  EXPECT_EQ(serialised(topics::kImuState, state), expected.bytes());
}

TEST(DdsWireBytes, TrailingPaddingIsCountedInTheOptions) {
  msg::KeyValue key_value{const_cast<char*>("fps"), const_cast<char*>("30")};
  msg::DiagnosticStatus status{diagnostic_msgs_msg_DiagnosticStatus_Constants_ERROR,
                               const_cast<char*>("cam"),
                               const_cast<char*>(""),
                               const_cast<char*>("hw"),
                               {1, 1, &key_value, false}};
  msg::DiagnosticArray array{makeHeader(2 * kNsPerSecond + 7, "w"), {1, 1, &status, false}};

  ExpectedBytes expected;
  expected.raw({0x00, 0x01, 0x00, 0x01});  // CDR_LE; options: 1 padding byte ends the payload
  expected.i32(2).u32(7);                  //  0: stamp
  expected.string("w");                    //  8: length 2 + "w\0" → 14
  expected.zeros(2);                       // 14 → 16 for the sequence length
  expected.u32(1);                         // 16: one DiagnosticStatus
  expected.u8(2);                          // 20: level = ERROR (octet, no alignment)
  expected.zeros(3);                       // 21 → 24 for the name's length
  expected.string("cam");                  // 24: → 32
  expected.string("");                     // 32: message, length 1 + "\0" → 37
  expected.zeros(3);                       // 37 → 40
  expected.string("hw");                   // 40: → 47
  expected.zeros(1);                       // 47 → 48
  expected.u32(1);                         // 48: one KeyValue
  expected.string("fps");                  // 52: → 60
  expected.string("30");                   // 60: length 3 + "30\0" → 67
  ASSERT_EQ(expected.offset(), 67u);
  expected.zeros(1);  // 67 → 68: Cyclone's padding to a multiple of 4

  EXPECT_EQ(serialised(topics::kDiagnostics, array), expected.bytes());
}

}  // namespace
}  // namespace vifusion::dds
