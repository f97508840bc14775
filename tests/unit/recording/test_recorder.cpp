// The threaded Recorder: everything pushed is written, in order, and reads back; producers never block and
// allocate nothing once the recording runs; a file that cannot be created is an error naming it.

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "recording_fixtures.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/recording/recorder.hpp"
#include "vifusion/recording/recording_reader.hpp"
#include "vifusion/test/counting_allocations.hpp"

namespace vifusion::recording::test {
namespace {

constexpr int kWarmUpFrames = 5;
constexpr int kFrames = 60;
constexpr int kImuPerFrame = 7;

TEST(Recorder, WritesEverythingPushedAndAllocatesNothingPerItem) {
  TempDir dir;
  RecorderOptions options;
  options.frame_ring = 4;
  Recorder recorder(dir / "live.mcap", recordingHeader(), options);
  // Frames are made before the count starts: making them allocates, pushing and writing must not.
  std::vector<RgbdFrame> frames;
  for (int k = 0; k < kFrames; ++k) frames.push_back(makeFrame(k));
  std::uint64_t heap_after_warm_up = 0;
  int imu = 0;
  for (int k = 0; k < kFrames; ++k) {
    if (k == kWarmUpFrames) heap_after_warm_up = vifusion::test::heapAllocationCount();
    for (int i = 0; i < kImuPerFrame; ++i, ++imu) ASSERT_TRUE(recorder.pushImu(makeImu(imu)));
    ASSERT_TRUE(recorder.pushSyncEdge(frames[k].t_ns - 1000, true, k));
    ASSERT_TRUE(recorder.pushClock(makeClock(k)));
    while (recorder.frameRingFull()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    ASSERT_TRUE(recorder.pushFrame(frames[k]));
  }
  // Let the recorder's thread write what is waiting, so its work is inside the count too.
  while (recorder.stats().written.frames < static_cast<std::uint64_t>(kFrames)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  const std::uint64_t allocations = vifusion::test::heapAllocationCount() - heap_after_warm_up;
  EXPECT_EQ(allocations, 0u) << "heap allocations while pushing and writing " << kFrames - kWarmUpFrames << " frames";

  ASSERT_TRUE(recorder.stop()) << recorder.stats().error;
  EXPECT_TRUE(recorder.stop()) << "stop() is idempotent";
  const RecorderStats stats = recorder.stats();
  EXPECT_FALSE(stats.recording);
  EXPECT_EQ(stats.written.frames, static_cast<std::uint64_t>(kFrames));
  EXPECT_EQ(stats.written.imu_samples, static_cast<std::uint64_t>(kFrames * kImuPerFrame));
  EXPECT_EQ(stats.written.sync_edges, static_cast<std::uint64_t>(kFrames));
  EXPECT_EQ(stats.frames_dropped + stats.imu_dropped + stats.edges_dropped + stats.clocks_dropped, 0u);
  EXPECT_FALSE(recorder.pushFrame(frames[0])) << "a stopped recorder takes nothing";
  EXPECT_EQ(recorder.stats().frames_dropped, 1u);

  RecordingReader reader(dir / "live.mcap");
  EXPECT_EQ(reader.note(), "");
  ASSERT_EQ(reader.frameCount(), static_cast<std::size_t>(kFrames));
  RgbdFrame frame;
  for (int k = 0; k < kFrames; ++k) {
    ASSERT_TRUE(reader.nextFrame(frame));
    EXPECT_TRUE(sameFrame(frame, frames[k])) << "frame " << k;
  }
  EXPECT_EQ(reader.imu().size(), static_cast<std::size_t>(kFrames * kImuPerFrame));
  EXPECT_EQ(reader.syncEdges().size(), static_cast<std::size_t>(kFrames));
}

// A full ring refuses the item (counted) instead of waiting: a camera's driver thread never blocks on the disk.
TEST(Recorder, AFullRingDropsAndCountsInsteadOfWaiting) {
  TempDir dir;
  RecorderOptions options;
  options.imu_ring = 1;
  Recorder recorder(dir / "full.mcap", recordingHeader(), options);
  int refused = 0;
  const auto start = std::chrono::steady_clock::now();
  for (int k = 0; k < 1000; ++k) refused += recorder.pushImu(makeImu(k)) ? 0 : 1;
  const double push_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  recorder.stop();
  EXPECT_EQ(recorder.stats().imu_dropped, static_cast<std::uint64_t>(refused));
  EXPECT_EQ(recorder.stats().written.imu_samples + recorder.stats().imu_dropped, 1000u);
  EXPECT_LT(push_ms, 1000.0) << "1000 pushes must not wait for the disk";
}

TEST(Recorder, AFileThatCannotBeCreatedIsAnErrorNamingIt) {
  TempDir dir;
  try {
    Recorder recorder(dir / "missing" / "x.mcap", recordingHeader());
    FAIL() << "recorded into a directory that does not exist";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("missing/x.mcap"), std::string::npos) << error.what();
  }
  RecorderOptions bad;
  bad.frame_ring = 0;
  try {
    Recorder recorder(dir / "x.mcap", recordingHeader(), bad);
    FAIL() << "accepted frame_ring 0";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("'frame_ring'"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace vifusion::recording::test
