// Publisher here, subscriber in another process (dds_test_peer): discovery and data over the loopback
// network, echo's output, the bytes that actually crossed the wire, and a late joiner of the map.

#include <gtest/gtest.h>

#include <chrono>
#include <sstream>
#include <thread>

#include "dds_test_support.hpp"
#include "sample_messages.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/dds/echo.hpp"
#include "vifusion/dds/writer.hpp"

namespace vifusion::dds {
namespace {

constexpr auto kPublishPeriod = std::chrono::milliseconds(50);
constexpr std::int64_t kPeerTimeoutMs = 20'000;

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> result;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) result.push_back(line);
  return result;
}

std::vector<std::string> peerArgs(const ParticipantOptions& options, std::vector<std::string> command) {
  std::vector<std::string> args = test::peerParticipantArgs(options);
  args.insert(args.end(), command.begin(), command.end());
  return args;
}

/// Calls publish() every period until the peer exits (it may not have discovered us for a while:
/// volatile samples sent before it matched are not for it); returns the peer's exit code.
template <typename Publish>
int publishUntilPeerExits(test::PeerProcess& peer, Publish&& publish) {
  while (peer.running()) {
    publish();
    std::this_thread::sleep_for(kPublishPeriod);
  }
  return peer.wait();
}

TEST(DdsTwoProcess, EchoPrintsOdometryFromAnotherProcess) {
  const ParticipantOptions options = test::loopbackOptions();
  const Participant participant(options);
  Writer writer(participant, topics::kOdometry);
  test::SampleMessages samples;
  test::PeerProcess peer(peerArgs(options, {"echo", "/vifusion/odometry", "3", std::to_string(kPeerTimeoutMs)}));
  std::uint32_t sequence = 0;
  const int code = publishUntilPeerExits(peer, [&] {
    samples.odometry.header.stamp.nanosec = ++sequence;
    writer.write(samples.odometry);
  });
  ASSERT_EQ(code, kEchoOk) << peer.err();
  const std::vector<std::string> printed = lines(peer.out());
  ASSERT_EQ(printed.size(), 3u) << peer.out();
  for (const std::string& line : printed) {
    EXPECT_TRUE(line.starts_with("{\"header\":{\"stamp\":{\"sec\":1700000000,\"nanosec\":")) << line;
    EXPECT_NE(
        line.find("},\"frame_id\":\"world\"},\"child_frame_id\":\"camera\",\"pose\":{\"pose\":{\"position\":{\"x\":"),
        std::string::npos)
        << line;
    EXPECT_NE(line.find("\"twist\":{\"twist\":{\"linear\":{\"x\":"), std::string::npos) << line;
    EXPECT_TRUE(line.ends_with("]}}")) << line;
  }
}

TEST(DdsTwoProcess, EchoPrintsEscapedDiagnostics) {
  const ParticipantOptions options = test::loopbackOptions();
  const Participant participant(options);
  Writer writer(participant, topics::kDiagnostics);
  const test::SampleMessages samples;
  test::PeerProcess peer(peerArgs(options, {"echo", "rt/diagnostics", "1", std::to_string(kPeerTimeoutMs)}));
  ASSERT_EQ(publishUntilPeerExits(peer, [&] { writer.write(samples.diagnostics); }), kEchoOk) << peer.err();
  EXPECT_EQ(peer.out(),
            "{\"header\":{\"stamp\":{\"sec\":1700000000,\"nanosec\":123456792},\"frame_id\":\"\"},\"status\":["
            "{\"level\":1,\"name\":\"vifusion: tracking\",\"message\":\"lost 3 frames\",\"hardware_id\":\"zr300-0042\","
            "\"values\":[{\"key\":\"frames\",\"value\":\"1234\"},"
            "{\"key\":\"quote \\\" and \\\\ newline \\n\",\"value\":\"\"}]},"
            "{\"level\":3,\"name\":\"vifusion: imu\",\"message\":\"\",\"hardware_id\":\"\",\"values\":[]}]}\n");
}

TEST(DdsTwoProcess, LateEchoGetsTheLastMapChunk) {
  const ParticipantOptions options = test::loopbackOptions();
  const Participant participant(options);
  Writer writer(participant, topics::kMap);
  const std::vector<MapPoint> first(2);
  const std::vector<MapPoint> last(5);
  ASSERT_TRUE(writer.write(makePointCloud2(1, "world", first)));
  ASSERT_TRUE(writer.write(makePointCloud2(2, "world", last)));
  // The peer starts after both writes and must still print the second chunk, and only it.
  test::PeerProcess peer(peerArgs(options, {"echo", "/vifusion/map", "1", std::to_string(kPeerTimeoutMs)}));
  ASSERT_EQ(peer.wait(), kEchoOk) << peer.err();
  EXPECT_TRUE(
      peer.out().starts_with("{\"header\":{\"stamp\":{\"sec\":0,\"nanosec\":2},\"frame_id\":\"world\"},"
                             "\"height\":1,\"width\":5,\"fields\":[{\"name\":\"x\",\"offset\":0,\"datatype\":7,"
                             "\"count\":1},"))
      << peer.out();
  EXPECT_TRUE(
      peer.out().ends_with("\"is_bigendian\":false,\"point_step\":36,\"row_step\":180,"
                           "\"data\":\"<sequence type: uint8, length: 180>\",\"is_dense\":true}\n"))
      << peer.out();
}

TEST(DdsTwoProcess, BytesOnTheWireAreXcdr1) {
  const ParticipantOptions options = test::loopbackOptions();
  const Participant participant(options);
  Writer writer(participant, topics::kPose);
  // A unit quaternion and short frame id, as test_wire_bytes.cpp's hand-worked PoseStamped.
  const msg::PoseStamped pose =
      makePoseStamped(1'700'000'000'123'456'789, "world",
                      SE3d(Eigen::Quaterniond(0.5, 0.5, 0.5, 0.5), Eigen::Vector3d(1.0, 2.0, -0.5)));
  test::PeerProcess peer(peerArgs(options, {"pose-bytes", std::to_string(kPeerTimeoutMs)}));
  ASSERT_EQ(publishUntilPeerExits(peer, [&] { writer.write(pose); }), 0) << peer.err();
  EXPECT_EQ(peer.out(),
            "00010000"  // CDR_LE, no end padding
            "00f15365"
            "15cd5b07"  // stamp
            "06000000"
            "776f726c6400"  // "world"
            "000000000000"  // pad 18 → 24
            "000000000000f03f"
            "0000000000000040"
            "000000000000e0bf"
            "000000000000e03f"
            "000000000000e03f"
            "000000000000e03f"
            "000000000000e03f\n");
}

}  // namespace
}  // namespace vifusion::dds
