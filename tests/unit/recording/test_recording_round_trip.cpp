// A recording written by RecordingFile reads back through RecordingReader bit for bit; cut anywhere, it reads
// back to its last complete frame; what is not a recording, or not one of this rig, is refused by name.

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "recording_fixtures.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/mcap/mcap_reader.hpp"
#include "vifusion/mcap/mcap_writer.hpp"
#include "vifusion/recording/open_recorded.hpp"
#include "vifusion/recording/recording_reader.hpp"

namespace vifusion::recording::test {
namespace {

constexpr int kFrames = 12;
constexpr int kImuSamples = 100;
constexpr int kEdges = 9;

/// Writes kFrames frames interleaved with IMU samples, edges, clock mappings and ground truth, as a live
/// recording or a simulated one would; small chunks, so a cut falls between many of them.
void writeRecording(const std::filesystem::path& path) {
  mcap::McapWriterOptions options;
  options.chunk_target_bytes = 8 * 1024;
  RecordingFile file(options);
  ASSERT_TRUE(file.open(path, recordingHeader())) << file.error();
  int imu = 0;
  for (int k = 0; k < kFrames; ++k) {
    const RgbdFrame frame = makeFrame(k);
    for (; imu < kImuSamples && makeImu(imu).t_ns <= frame.t_ns; ++imu) ASSERT_TRUE(file.writeImu(makeImu(imu), 1));
    if (k < kEdges) {
      ASSERT_TRUE(file.writeSyncEdge(frame.t_ns - 3'200'000, true, k, 1));
    }
    ASSERT_TRUE(file.writeClock(makeClock(k), 1));
    ASSERT_TRUE(file.writeFrame(frame, 1)) << file.error();
    ASSERT_TRUE(
        file.writeGroundTruthPose(frame.t_ns, SE3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(k, 0, 0)), 1));
  }
  for (; imu < kImuSamples; ++imu) ASSERT_TRUE(file.writeImu(makeImu(imu), 1));
  // A transfer of two packets and a short tail (which carries no whole packet and is not kept).
  std::vector<std::uint8_t> transfer(2 * motion::kPacketBytes + 10);
  for (std::size_t i = 0; i < transfer.size(); ++i) transfer[i] = static_cast<std::uint8_t>(i * 7);
  ASSERT_TRUE(file.writeMotionTransfer(kStartNs + 123, 42, transfer, 1));
  ASSERT_TRUE(file.close()) << file.error();
  EXPECT_EQ(file.counts().frames, static_cast<std::uint64_t>(kFrames));
}

TEST(RecordingRoundTrip, EverythingWrittenReadsBackBitForBit) {
  TempDir dir;
  writeRecording(dir / "a.mcap");
  RecordingReader reader(dir / "a.mcap");
  EXPECT_EQ(reader.note(), "");
  EXPECT_EQ(reader.source(), "zr300:SN_TEST");
  EXPECT_EQ(reader.mode(), "rgbdi");
  ASSERT_EQ(reader.frameCount(), static_cast<std::size_t>(kFrames));
  RgbdFrame frame;
  for (int k = 0; k < kFrames; ++k) {
    ASSERT_TRUE(reader.nextFrame(frame)) << "frame " << k;
    EXPECT_TRUE(sameFrame(frame, makeFrame(k))) << "frame " << k;
  }
  EXPECT_FALSE(reader.nextFrame(frame));

  ASSERT_EQ(reader.imu().size(), static_cast<std::size_t>(kImuSamples));
  for (int k = 0; k < kImuSamples; ++k) {
    const ImuSample want = makeImu(k);
    EXPECT_EQ(reader.imu()[k].t_ns, want.t_ns);
    EXPECT_EQ(reader.imu()[k].gyro_rad_s, want.gyro_rad_s) << "sample " << k;
    EXPECT_EQ(reader.imu()[k].accel_mps2, want.accel_mps2) << "sample " << k;
  }
  ASSERT_EQ(reader.syncEdges().size(), static_cast<std::size_t>(kEdges));
  EXPECT_EQ(reader.syncEdges()[4].t_ns, makeFrame(4).t_ns - 3'200'000);
  EXPECT_EQ(reader.syncEdges()[4].sequence, 4u);
  ASSERT_EQ(reader.clockRecords().size(), static_cast<std::size_t>(kFrames));
  EXPECT_EQ(reader.clockRecords()[5].ref_host_ns, makeClock(5).ref_host_ns);
  EXPECT_EQ(reader.clockRecords()[5].skew, makeClock(5).skew);
  ASSERT_EQ(reader.motionPackets().size(), 2u);
  EXPECT_EQ(reader.motionPackets()[1].host_receive_ns, kStartNs + 123);
  EXPECT_EQ(reader.motionPackets()[1].transfer_index, 42u);
  EXPECT_EQ(reader.motionPackets()[1].bytes[0], static_cast<std::uint8_t>(motion::kPacketBytes * 7));
  ASSERT_EQ(reader.groundTruth().size(), static_cast<std::size_t>(kFrames));
  EXPECT_EQ(reader.groundTruth()[7].T_world_body.translation().x(), 7.0);

  // The calibration comes back from the recording's YAML: both cameras, the extrinsics, the time shift.
  const RigCalibration want = rigCalibration();
  const RigCalibration& got = reader.calibration();
  EXPECT_EQ(got.camera.fy, want.camera.fy);
  ASSERT_TRUE(got.depth_camera.has_value());
  EXPECT_EQ(got.depth_camera->camera.fx, want.depth_camera->camera.fx);
  EXPECT_LT((got.depth_camera->T_C_D.inverse() * want.depth_camera->T_C_D).log().norm(), 1e-15);
  EXPECT_LT((got.T_S_C.inverse() * want.T_S_C).log().norm(), 1e-15);
  EXPECT_EQ(got.time_shift_cam_imu_ns, want.time_shift_cam_imu_ns);

  // The same through the source spec of `vifusion run`.
  const auto source = openRecorded("rec:" + (dir / "a.mcap").string());
  EXPECT_EQ(source->frameCount(), static_cast<std::size_t>(kFrames));
}

// Issue 22: an IMU message out of time order (here one written twice) is left out and named; the recording
// still opens, with every other sample.
TEST(RecordingRoundTrip, AnImuMessageOutOfOrderIsLeftOutAndNamed) {
  TempDir dir;
  RecordingFile file{mcap::McapWriterOptions()};
  ASSERT_TRUE(file.open(dir / "a.mcap", recordingHeader())) << file.error();
  for (int k = 0; k < 10; ++k) {
    ASSERT_TRUE(file.writeImu(makeImu(k), 1));
    if (k == 5) {
      ASSERT_TRUE(file.writeImu(makeImu(k), 1));
    }
  }
  ASSERT_TRUE(file.writeFrame(makeFrame(0), 1)) << file.error();
  ASSERT_TRUE(file.close()) << file.error();
  RecordingReader reader(dir / "a.mcap");
  EXPECT_EQ(reader.imu().size(), 10u);
  ASSERT_EQ(reader.skippedImuRows().size(), 1u);
  EXPECT_NE(reader.skippedImuRows()[0].find("a.mcap: /camera/imu message "), std::string::npos)
      << reader.skippedImuRows()[0];
  EXPECT_NE(reader.skippedImuRows()[0].find(": time goes backwards by 0 ns"), std::string::npos);
}

// A recording cut anywhere (SIGKILL, power loss, full disk) reads back to its last complete frame: every
// frame delivered is whole and bit-exact, and they are the first ones written.
TEST(RecordingRoundTrip, ACutRecordingReadsBackToItsLastCompleteFrame) {
  TempDir dir;
  writeRecording(dir / "whole.mcap");
  std::ifstream in(dir / "whole.mcap", std::ios::binary);
  const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // The schemas (their ros2msg texts) and the first chunk, which holds the recording info, come first: a cut
  // before that chunk's end is refused, every later one reads.
  const mcap::McapReader whole((dir / "whole.mcap").string());
  ASSERT_FALSE(whole.chunks().empty());
  const std::uint64_t first_chunk_end = whole.chunks().front().offset + whole.chunks().front().record_bytes;
  constexpr int kCuts = 40;
  int readable = 0;
  std::size_t previous_frames = 0;
  for (int c = 1; c <= kCuts; ++c) {
    const std::size_t cut = bytes.size() * c / (kCuts + 1);
    const std::filesystem::path path = dir / ("cut_" + std::to_string(c) + ".mcap");
    std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(cut));
    try {
      RecordingReader reader(path);
      ++readable;
      EXPECT_GE(cut, first_chunk_end);
      if (reader.frameCount() < static_cast<std::size_t>(kFrames)) {
        EXPECT_NE(reader.note(), "") << "cut at " << cut << " of " << bytes.size();
      }
      EXPECT_GE(reader.frameCount(), previous_frames) << "a longer prefix holds fewer frames";
      previous_frames = reader.frameCount();
      RgbdFrame frame;
      for (std::size_t k = 0; k < reader.frameCount(); ++k) {
        ASSERT_TRUE(reader.nextFrame(frame));
        EXPECT_TRUE(sameFrame(frame, makeFrame(static_cast<int>(k)))) << "cut at " << cut << ", frame " << k;
      }
      EXPECT_FALSE(reader.nextFrame(frame));
    } catch (const Error& error) {
      // Only a cut before the first chunk (the recording info's, written as the recording starts) is refused,
      // and it says so.
      EXPECT_NE(std::string(error.what()).find("recording_info"), std::string::npos) << error.what();
      EXPECT_LT(cut, first_chunk_end) << error.what();
    }
  }
  EXPECT_GT(readable, kCuts * 3 / 4);
  EXPECT_GT(previous_frames, static_cast<std::size_t>(kFrames) * 3 / 4);
}

TEST(RecordingRoundTrip, AnMcapFileWithoutRecordingInfoIsNotARecording) {
  TempDir dir;
  mcap::McapWriter writer;
  ASSERT_TRUE(writer.open((dir / "other.mcap").string()));
  const std::uint16_t channel = writer.registerChannel("/chatter", 0, "json");
  const std::uint8_t hello[] = {'{', '}'};
  ASSERT_TRUE(writer.write(channel, 0, 1, 1, hello));
  ASSERT_TRUE(writer.close());
  try {
    RecordingReader reader(dir / "other.mcap");
    FAIL() << "accepted an MCAP file without /vifusion/recording_info";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("other.mcap: not a vifusion recording"), std::string::npos)
        << error.what();
  }
  EXPECT_THROW(openRecorded("rec:"), Error);
}

TEST(RecordingRoundTrip, AFrameOfAnotherSizeIsRefusedByName) {
  TempDir dir;
  RecordingFile file;
  ASSERT_TRUE(file.open(dir / "a.mcap", recordingHeader()));
  RgbdFrame frame = makeFrame(0);
  frame.rgb.resize(kWidth / 2, kHeight);
  EXPECT_FALSE(file.writeFrame(frame, 1));
  EXPECT_TRUE(file.failed());
  EXPECT_NE(file.error().find("frame 0: images of 32x24 depth and 16x24 colour"), std::string::npos) << file.error();
  EXPECT_FALSE(file.writeImu(makeImu(0), 1)) << "a failed recording writes nothing more";
}

}  // namespace
}  // namespace vifusion::recording::test
