// vifusiond's steady state on the live source allocates nothing per frame (issue 17; the recorded source's
// counterpart is tests/service/test_daemon_allocations.cpp). Every thread of the service's per-frame path runs
// as in vifusiond: the scripted ZR300's camera and motion-module driver threads (the real V4L2 stream, USB
// and clock-mapping code against the scripted devices), the daemon's frame reader pulling assembled frames
// into the camera ring, the SLAM thread (SlamWorker, rgbdi, its IMU from the source's LiveImuFeed) and the
// publisher (odometry, pose, tf, imu_state and status over DDS on loopback). The camera replays the
// synthetic living room (2 s), which tracks without a lost frame, so every frame goes through tracking,
// the estimator and fusion.
//
// After a warm-up of kWarmUpFrames, until the last frame is published: no C++ heap allocation anywhere in the
// process (the operator-new replacement counts every thread), and malloc's in-use bytes stay flat.

#include <gtest/gtest.h>
#include <malloc.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <random>
#include <thread>

#include "scripted_replay.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/daemon/frame_reader.hpp"
#include "vifusion/daemon/publisher.hpp"
#include "vifusion/daemon/shared_state.hpp"
#include "vifusion/daemon/slam_worker.hpp"
#include "vifusion/dds/participant.hpp"
#include "vifusion/gpu/gpu_context.hpp"
#include "vifusion/test/counting_allocations.hpp"
#include "vifusion/test/dds_domains.hpp"
#include "vifusion/zr300/open_zr300.hpp"

namespace vifusion::live_test {
namespace {

using daemon::FrameSlot;
using daemon::Publisher;
using daemon::SharedState;
using daemon::SlamWorker;
using daemon::SlamWorkerOptions;

/// Frames before the count starts: the ring slots, the estimator's window and the map's first frames fill
/// their reserved storage once.
constexpr std::uint64_t kWarmUpFrames = 20;
/// Freed blocks that glibc or the driver keep cached move the in-use bytes by a few blocks; a per-frame
/// allocation that is not freed would grow them by far more over 40 frames of 320×240 images.
constexpr long long kMallocGrowthLimitBytes = 64 * 1024;
constexpr std::int64_t kRunLimitNs = 300 * kNsPerSecond;

std::size_t mallocInUseBytes() { return mallinfo2().uordblks; }

void waitFor(const std::function<bool()>& done) {
  const std::int64_t give_up_ns = monotonicNowNs() + kRunLimitNs;
  while (!done() && monotonicNowNs() < give_up_ns) std::this_thread::sleep_for(std::chrono::milliseconds(2));
}

TEST(LiveDaemonSteadyState, AllocatesNothingPerFrame) {
  const std::filesystem::path work = VIFUSION_LIVE_ALLOCATIONS_DIR;
  std::filesystem::remove_all(work);
  std::filesystem::create_directories(work);
  Replay replay = prepareReplay(VIFUSION_RECORDING_DIR, work);
  ASSERT_GT(replay.frames, kWarmUpFrames + 20);

  const std::unique_ptr<zr300::Zr300Source> source =
      zr300::openZr300({}, replay.files / "calibration.yaml", zr300::Zr300Options{},
                       std::make_unique<ScriptedCamera>(std::move(replay.script)));
  ASSERT_NE(source->imuFeed(), nullptr);
  const std::unique_ptr<gpu::GpuContext> context = gpu::GpuContext::create(gpu::GpuOptions{}.withEnvironment());
  slam::SlamOptions slam_options;
  slam_options.mode = slam::SlamMode::kRgbdInertial;
  slam_options.map.capacity = 200'000;
  slam::Slam pipeline(*context, source->calibration(), slam_options);

  FrameSlot prototype;  // every ring slot sized for the calibration's images, as vifusiond does
  prototype.frame.depth.resize(source->calibration().camera.width, source->calibration().camera.height);
  prototype.frame.rgb.resize(source->calibration().camera.width, source->calibration().camera.height);
  SharedState state(4, prototype, 64);

  std::mt19937_64 random{std::random_device{}()};
  config::DaemonConfig config;
  config.mode = "rgbdi";
  // A domain of its own: discovering a parallel test's participant would add its proxies' malloc.
  config.dds.domain = test::kLiveDaemonAllocationsDomain;
  config.dds.config = VIFUSION_DDS_LOOPBACK_CONFIG;
  config.dds.partition = "live_daemon_allocations_" + std::to_string(::getpid()) + "_" + std::to_string(random());
  config.status_period_s = 0.05;
  const dds::Participant participant(
      dds::ParticipantOptions{config.dds.domain, config.dds.config, config.dds.partition});
  Publisher publisher(participant, config, slam_options.map.confidence_threshold, source->calibration().T_S_C, state);
  SlamWorkerOptions worker_options;
  worker_options.out_dir = work / "out";
  worker_options.imu = source->imuFeed();
  worker_options.expected_frames = daemon::kLiveTrajectoryReserveFrames;  // as vifusiond for a live source
  SlamWorker worker(pipeline, slam_options.map, worker_options, state);

  std::thread reader_thread([&] { daemon::runFrameReader(*source, false, state); });
  std::thread slam_thread([&] { worker.run(); });
  std::thread publisher_thread([&] { publisher.run(); });

  waitFor([&] { return state.frames_processed.load() >= kWarmUpFrames; });
  const std::uint64_t heap_after_warm_up = test::heapAllocationCount();
  const std::size_t malloc_after_warm_up = mallocInUseBytes();
  // The live source never ends by itself: stop it once every frame of the replay went through SLAM and out.
  const std::uint64_t frames = replay.frames;
  waitFor([&] { return state.frames_processed.load() >= frames && state.results.size() == 0; });
  std::this_thread::sleep_for(std::chrono::milliseconds(100));  // the publisher finishes what it took last
  const std::uint64_t heap_allocations = test::heapAllocationCount() - heap_after_warm_up;
  const long long malloc_growth =
      static_cast<long long>(mallocInUseBytes()) - static_cast<long long>(malloc_after_warm_up);
  const std::uint64_t processed = state.frames_processed.load();

  source->requestStop();
  reader_thread.join();
  slam_thread.join();
  publisher_thread.join();

  std::printf("live rgbdi: %llu frames after a %llu-frame warm-up: %llu C++ allocations, malloc in-use %+lld bytes\n",
              static_cast<unsigned long long>(processed - kWarmUpFrames),
              static_cast<unsigned long long>(kWarmUpFrames), static_cast<unsigned long long>(heap_allocations),
              malloc_growth);
  ASSERT_EQ(processed, frames) << "not every frame of the replay reached the SLAM thread";
  EXPECT_EQ(heap_allocations, 0u) << "C++ heap allocations in " << frames - kWarmUpFrames << " live frames";
  EXPECT_LT(malloc_growth, kMallocGrowthLimitBytes);
  // The path really ran end to end: every frame tracked, with its IMU samples, and published.
  EXPECT_EQ(state.exit_code.load(), 0);
  EXPECT_EQ(state.lost_frames.load(), 0u) << "lost frames skip fusion: the path under test did not fully run";
  EXPECT_EQ(state.imu_issue_frames.load(), 0u) << "frames whose IMU samples were refused";
  EXPECT_EQ(state.results.overruns(), 0u);
  EXPECT_EQ(source->stats().kernel_timestamps, 0u) << "frames not stamped by the motion module's events";
}

}  // namespace
}  // namespace vifusion::live_test
