// vifusiond's steady state allocates nothing per frame. The daemon's own pieces run on their own
// threads, as in vifusiond: the camera ring → SlamWorker (the SLAM thread, GPU pipeline) → output
// ring → Publisher (odometry, pose, tf and status over DDS on loopback). This thread plays the camera
// driver: it copies each frame into the slot the ring handed back and pushes it, as a V4L2 reader
// would (decoding a dataset's PNGs is the replay reader's business and allocates; it is not on a
// robot's per-frame path).
//
// After a warm-up of 50 frames, over 250 more: no C++ heap allocation anywhere in the process (the
// operator-new replacement counts every thread) and malloc's in-use bytes stay flat (they also see the
// C allocations of Cyclone DDS and the Vulkan driver). The frames are a rendered pan that tracks without
// a lost frame, so every frame goes through tracking AND fusion. The map snapshot
// (map_publish_period_s) is off: it is periodic, not per frame, and allocates while the map grows
// (RgbdSlam::exportMap).

#include <gtest/gtest.h>
#include <malloc.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <filesystem>
#include <random>
#include <thread>
#include <vector>

#include "vifusion/core/time.hpp"
#include "vifusion/daemon/publisher.hpp"
#include "vifusion/daemon/shared_state.hpp"
#include "vifusion/daemon/slam_worker.hpp"
#include "vifusion/dds/reader.hpp"
#include "vifusion/gpu/gpu_context.hpp"
#include "vifusion/scene/living_room.hpp"
#include "vifusion/scene/look_at.hpp"
#include "vifusion/scene/renderer.hpp"
#include "vifusion/scene/row_pool.hpp"
#include "vifusion/test/counting_allocations.hpp"

namespace vifusion::daemon {
namespace {

constexpr std::int64_t kFramePeriodNs = 33'333'333;

std::size_t mallocInUseBytes() { return mallinfo2().uordblks; }

RigCalibration panCalibration() {
  RigCalibration calibration;
  calibration.camera = PinholeCamera::create(160, 120, 120.0, 120.0, 79.5, 59.5);
  calibration.depth_scale_m = 0.001;
  return calibration;
}

/// 40 noise-free frames of the living room along a slow pan (2 mm and 0.23° per frame), rendered once.
std::vector<RgbdFrame> renderPan(const PinholeCamera& camera) {
  const scene::LivingRoom room;
  scene::RowPool pool(2);
  const scene::Renderer renderer(room, pool);
  std::vector<RgbdFrame> frames;
  Image<float> depth_m(camera.width, camera.height);
  for (int i = 0; i < 40; ++i) {
    const double yaw_rad = 0.004 * i;
    const Eigen::Vector3d eye_W(1.1 + 0.002 * i, 1.3, 0.8);
    const Eigen::Vector3d target_W = eye_W + Eigen::Vector3d(std::sin(yaw_rad), -0.25, -std::cos(yaw_rad));
    RgbdFrame frame;
    frame.depth = Image<std::uint16_t>(camera.width, camera.height);
    frame.rgb = Image<Rgb8>(camera.width, camera.height);
    frame.depth_scale_m = 0.001;
    renderer.render(scene::lookAt(eye_W, target_W), camera, frame.rgb.view(), depth_m.view());
    for (int y = 0; y < camera.height; ++y) {
      for (int x = 0; x < camera.width; ++x) {
        frame.depth(x, y) = static_cast<std::uint16_t>(std::lround(depth_m(x, y) * 1000.0f));
      }
    }
    frames.push_back(std::move(frame));
  }
  return frames;
}

/// Frame i of the sequence played forwards, backwards, forwards…: a continuous camera motion of any
/// length, so the pipeline keeps tracking and fusing instead of jumping back to the start.
const RgbdFrame& pingPong(const std::vector<RgbdFrame>& frames, std::size_t i) {
  const std::size_t period = 2 * (frames.size() - 1);
  const std::size_t k = i % period;
  return frames[k < frames.size() ? k : period - k];
}

/// What a camera driver does per frame: fill the slot the ring handed back. Copy-assigning the images
/// reuses the slot's buffers; it allocates only while a slot that never held a frame comes round (the
/// SLAM thread's own slot enters the ring at its first pop), i.e. in the warm-up.
void fillSlot(const RgbdFrame& source, std::size_t i, FrameSlot& slot) {
  slot.frame = source;
  slot.frame.t_ns = static_cast<std::int64_t>(i) * kFramePeriodNs;
  slot.frame.index = static_cast<std::int64_t>(i);
  slot.read_ns = monotonicNowNs();
}

/// Waits until the SLAM thread processed `frames` frames and the publisher emptied the output ring,
/// then a little longer, so the publisher has finished publishing what it took last.
void waitUntilPublished(const SharedState& state, std::uint64_t frames) {
  const std::int64_t deadline_ns = monotonicNowNs() + 60 * kNsPerSecond;
  while ((state.frames_processed.load() < frames || state.results.size() > 0) && monotonicNowNs() < deadline_ns) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
}

TEST(DaemonSteadyState, AllocatesNothingPerFrame) {
  const RigCalibration calibration = panCalibration();
  const std::vector<RgbdFrame> sequence = renderPan(calibration.camera);

  const std::unique_ptr<gpu::GpuContext> context = gpu::GpuContext::create(gpu::GpuOptions{}.withEnvironment());
  slam::SlamOptions slam_options;
  slam_options.map.capacity = 200'000;
  slam::RgbdSlam pipeline(*context, calibration, slam_options);

  constexpr std::size_t kWarmUp = 50;
  constexpr std::size_t kFrames = 300;
  FrameSlot slot;
  slot.frame = sequence.front();  // every ring slot sized like a frame, as vifusiond does
  SharedState state(4, slot, 64);

  std::mt19937_64 random{std::random_device{}()};
  config::DaemonConfig config;
  config.dds.domain = std::uniform_int_distribution<std::uint32_t>(1, 200)(random);
  config.dds.config = VIFUSION_DDS_LOOPBACK_CONFIG;
  config.dds.partition = "daemon_allocations_" + std::to_string(::getpid()) + "_" + std::to_string(random());
  config.status_period_s = 0.05;  // several status messages inside the measured window
  const dds::Participant participant(dds::ParticipantOptions{config.dds.domain, config.dds.config, config.dds.partition});
  // Proof that the publisher really published in the window: it keeps the last 10 odometry samples.
  dds::Reader odometry(participant, dds::topics::kOdometry);
  Publisher publisher(participant, config, slam_options.map.confidence_threshold, state);

  SlamWorkerOptions worker_options;
  worker_options.out_dir = std::filesystem::path(VIFUSION_SERVICE_WORK_DIR) / "daemon_allocations";
  worker_options.expected_frames = kFrames;
  SlamWorker worker(pipeline, slam_options.map, worker_options, state);
  std::thread slam_thread([&] { worker.run(); });
  std::thread publisher_thread([&] { publisher.run(); });

  const std::uint64_t heap_at_start = test::heapAllocationCount();
  std::uint64_t heap_after_warm_up = 0;
  std::size_t malloc_after_warm_up = 0;
  for (std::size_t i = 0; i < kFrames; ++i) {
    if (i == kWarmUp) {
      waitUntilPublished(state, kWarmUp);
      heap_after_warm_up = test::heapAllocationCount();
      malloc_after_warm_up = mallocInUseBytes();
    }
    fillSlot(pingPong(sequence, i), i, slot);
    // Lossless, like a dataset replay: wait for a free slot rather than count an overrun.
    while (!state.frames.tryPush(std::move(slot))) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  waitUntilPublished(state, kFrames);
  const std::uint64_t heap_allocations = test::heapAllocationCount() - heap_after_warm_up;
  const auto malloc_growth = static_cast<long long>(mallocInUseBytes()) - static_cast<long long>(malloc_after_warm_up);

  std::printf("warm-up (%zu frames): %llu C++ allocations; next %zu frames: %llu, malloc in-use %+lld bytes\n", kWarmUp,
              static_cast<unsigned long long>(heap_after_warm_up - heap_at_start), kFrames - kWarmUp,
              static_cast<unsigned long long>(heap_allocations), malloc_growth);
  state.source_done = true;
  slam_thread.join();
  publisher_thread.join();

  EXPECT_EQ(heap_allocations, 0u) << "C++ heap allocations in " << kFrames - kWarmUp << " frames";
  // Freed blocks that glibc or the driver keep cached move the in-use bytes by a few blocks; any
  // per-frame allocation that is not freed would grow them by far more than 64 KiB over 250 frames.
  EXPECT_LT(malloc_growth, 64 * 1024) << "bytes of malloc growth in " << kFrames - kWarmUp << " frames";

  // The path really ran end to end: every frame went through SLAM and out of the publisher.
  EXPECT_EQ(state.exit_code.load(), 0);
  EXPECT_EQ(state.frames_processed.load(), kFrames);
  EXPECT_EQ(state.results.overruns(), 0u) << "the publisher fell behind";
  EXPECT_EQ(state.lost_frames.load(), 0u) << "lost frames skip fusion: the path under test did not fully run";
  std::int64_t newest_stamp_ns = -1;
  while (odometry.take([&](const dds::msg::Odometry& message) {
    newest_stamp_ns = std::max(newest_stamp_ns, message.header.stamp.sec * kNsPerSecond + message.header.stamp.nanosec);
  }) > 0) {
  }
  EXPECT_EQ(newest_stamp_ns, static_cast<std::int64_t>(kFrames - 1) * kFramePeriodNs)
      << "the last frame's odometry was not published";
}

}  // namespace
}  // namespace vifusion::daemon
