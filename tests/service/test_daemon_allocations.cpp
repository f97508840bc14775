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
// (Slam::exportMap).
//
// In rgbdi mode the SLAM thread also hands each frame the IMU stream (RecordedImuFeed, as vifusiond
// does for a recorded source) and the publisher adds rt/vifusion/imu_state and the estimator's
// covariances: the camera follows a smooth B-spline (at rest until t = 0, then a pan back and forth),
// every frame is rendered at its pose on the spline and the IMU samples are simulated from the same
// spline without noise, so the estimator runs on every frame and refuses none of them.

#include <gtest/gtest.h>
#include <malloc.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <random>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "vifusion/core/imu_feed.hpp"
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
#include "vifusion/sim/imu_simulator.hpp"
#include "vifusion/sim/se3_spline.hpp"
#include "vifusion/test/counting_allocations.hpp"
#include "vifusion/test/dds_domains.hpp"

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

/// Renders one frame of the living room seen from T_W_C (room frame, y up).
RgbdFrame renderFrame(const scene::Renderer& renderer, const PinholeCamera& camera, const SE3d& T_W_C,
                      Image<float>& depth_m) {
  RgbdFrame frame;
  frame.depth = Image<std::uint16_t>(camera.width, camera.height);
  frame.rgb = Image<Rgb8>(camera.width, camera.height);
  frame.depth_scale_m = 0.001;
  renderer.render(T_W_C, camera, frame.rgb.view(), depth_m.view());
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      frame.depth(x, y) = static_cast<std::uint16_t>(std::lround(depth_m(x, y) * 1000.0f));
    }
  }
  return frame;
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
    frames.push_back(renderFrame(renderer, camera, scene::lookAt(eye_W, target_W), depth_m));
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

/// A camera + IMU recording for rgbdi mode: `frames` frames at kFramePeriodNs from t = 0 and the IMU
/// stream from before the first frame (the estimator's gravity window) to after the last.
struct InertialSequence {
  std::vector<RgbdFrame> frames;
  std::vector<ImuSample> imu;
  /// Truth at the last frame in the map world W (the first camera's frame): the IMU's velocity [m/s] and
  /// the unit vector along gravity.
  Eigen::Vector3d last_v_W_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d down_W = Eigen::Vector3d::Zero();
};

/// The rig is the camera alone (T_S_C = identity: the IMU sits at the camera), so the spline of S is
/// the camera's. The motion is the pan above made smooth: at rest until t = 0, then the eye slides 8 cm
/// sideways and the view turns 0.16 rad and back, s(t) = (1 − cos(2π t / 2.7 s)) / 2 of the way.
InertialSequence renderInertialSequence(const RigCalibration& calibration, std::size_t frames) {
  constexpr std::int64_t kKnotNs = 100'000'000;
  constexpr std::int64_t kStartNs = -600'000'000;
  const std::int64_t end_ns = static_cast<std::int64_t>(frames) * kFramePeriodNs + 200'000'000;
  const auto pose_at = [](std::int64_t t_ns) {
    const double t_s = std::max(0.0, nsToSeconds(t_ns));
    const double s = 0.5 * (1.0 - std::cos(2.0 * M_PI * t_s / 2.7));
    const double yaw_rad = 0.16 * s;
    const Eigen::Vector3d eye_W(1.1 + 0.08 * s, 1.3, 0.8);
    return scene::lookAt(eye_W, eye_W + Eigen::Vector3d(std::sin(yaw_rad), -0.25, -std::cos(yaw_rad)));
  };
  // Control point m belongs to t0 + (m − 2)·Δt (Se3Spline::controlCentreTimeNs); enough of them for the
  // spline to cover [kStartNs + Δt, end_ns].
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Quaterniond> rotations;
  for (int m = 0; kStartNs + (m - sim::Se3Spline::kOrder) * kKnotNs <= end_ns; ++m) {
    const SE3d T_W_S = pose_at(kStartNs + (m - 2) * kKnotNs);
    positions.push_back(T_W_S.translation());
    rotations.push_back(T_W_S.quaternion());
  }
  const sim::Se3Spline spline(kStartNs, kKnotNs, positions, rotations);

  sim::ImuSimOptions imu_options;
  imu_options.noise = calibration.imu;
  imu_options.g_W_mps2 = Eigen::Vector3d(0.0, -calibration.imu.gravity_mps2, 0.0);  // the room is y-up
  imu_options.add_noise = false;
  imu_options.add_biases = false;
  imu_options.t_begin_ns = kStartNs + kKnotNs;
  imu_options.t_end_ns = end_ns;
  InertialSequence sequence;
  sequence.imu = sim::simulateImu(spline, imu_options).samples;
  const Eigen::Matrix3d R_W_room = spline.pose(0).rotationMatrix().transpose();  // W = S at frame 0
  sequence.last_v_W_mps = R_W_room * spline.kinematics(static_cast<std::int64_t>(frames - 1) * kFramePeriodNs).v_W_mps;
  sequence.down_W = R_W_room * -Eigen::Vector3d::UnitY();

  const scene::LivingRoom room;
  scene::RowPool pool(2);
  const scene::Renderer renderer(room, pool);
  Image<float> depth_m(calibration.camera.width, calibration.camera.height);
  for (std::size_t i = 0; i < frames; ++i) {
    const SE3d T_W_C = spline.pose(static_cast<std::int64_t>(i) * kFramePeriodNs) * calibration.T_S_C;
    sequence.frames.push_back(renderFrame(renderer, calibration.camera, T_W_C, depth_m));
  }
  return sequence;
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

constexpr std::size_t kWarmUp = 50;
constexpr std::size_t kFrames = 300;

/// The newest header stamp among the samples a reader kept [ns]; −1 if none. `newest` (if given)
/// receives a copy of that sample (its strings are the reader's: do not follow them).
template <typename Msg>
std::int64_t newestStampNs(dds::Reader<Msg>& reader, Msg* newest = nullptr) {
  std::int64_t newest_ns = -1;
  while (reader.take([&](const Msg& message) {
    if (dds::toNs(message.header.stamp) <= newest_ns) return;
    newest_ns = dds::toNs(message.header.stamp);
    if (newest != nullptr) *newest = message;
  }) > 0) {
  }
  return newest_ns;
}

Eigen::Vector3d toEigen(const dds::msg::Vector3& v) { return {v.x, v.y, v.z}; }

/// vifusiond's per-frame path in `mode` over kFrames frames (frame(i) gives frame i; `imu` is the
/// recording's IMU stream, empty in rgbd mode); checks the allocation counts and that every frame went
/// through SLAM and out of the publisher.
void expectNoAllocationPerFrame(const std::string& mode, const RigCalibration& calibration,
                                const std::function<const RgbdFrame&(std::size_t)>& frame,
                                const InertialSequence* inertial) {
  const std::span<const ImuSample> imu =
      inertial != nullptr ? std::span<const ImuSample>(inertial->imu) : std::span<const ImuSample>();
  const std::unique_ptr<gpu::GpuContext> context = gpu::GpuContext::create(gpu::GpuOptions{}.withEnvironment());
  slam::SlamOptions slam_options;
  slam_options.mode = slam::slamModeFromName(mode);
  slam_options.map.capacity = 200'000;
  slam::Slam pipeline(*context, calibration, slam_options);

  FrameSlot slot;
  slot.frame = frame(0);  // every ring slot sized like a frame, as vifusiond does
  SharedState state(4, slot, 64);

  std::mt19937_64 random{std::random_device{}()};
  config::DaemonConfig config;
  config.mode = mode;
  // A domain no parallel test uses: discovering a foreign participant would add its proxies' malloc.
  config.dds.domain = mode == "rgbd" ? test::kDaemonAllocationsRgbdDomain : test::kDaemonAllocationsRgbdiDomain;
  config.dds.config = VIFUSION_DDS_LOOPBACK_CONFIG;
  config.dds.partition = "daemon_allocations_" + std::to_string(::getpid()) + "_" + std::to_string(random());
  config.status_period_s = 0.05;  // several status messages inside the measured window
  const dds::Participant participant(
      dds::ParticipantOptions{config.dds.domain, config.dds.config, config.dds.partition});
  // Proof that the publisher really published in the window: the readers keep the last 10 samples.
  dds::Reader odometry(participant, dds::topics::kOdometry);
  dds::Reader imu_state(participant, dds::topics::kImuState);
  Publisher publisher(participant, config, slam_options.map.confidence_threshold, calibration.T_S_C, state);

  RecordedImuFeed imu_feed(imu);
  SlamWorkerOptions worker_options;
  worker_options.out_dir = std::filesystem::path(VIFUSION_SERVICE_WORK_DIR) / ("daemon_allocations_" + mode);
  worker_options.expected_frames = kFrames;
  worker_options.imu = imu.empty() ? nullptr : &imu_feed;
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
    fillSlot(frame(i), i, slot);
    // Lossless, like a dataset replay: wait for a free slot rather than count an overrun.
    while (!state.frames.tryPush(std::move(slot))) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  waitUntilPublished(state, kFrames);
  const std::uint64_t heap_allocations = test::heapAllocationCount() - heap_after_warm_up;
  const auto malloc_growth = static_cast<long long>(mallocInUseBytes()) - static_cast<long long>(malloc_after_warm_up);

  std::printf("%s: warm-up (%zu frames): %llu C++ allocations; next %zu frames: %llu, malloc in-use %+lld bytes\n",
              mode.c_str(), kWarmUp, static_cast<unsigned long long>(heap_after_warm_up - heap_at_start),
              kFrames - kWarmUp, static_cast<unsigned long long>(heap_allocations), malloc_growth);
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
  const std::int64_t last_stamp_ns = static_cast<std::int64_t>(kFrames - 1) * kFramePeriodNs;
  EXPECT_EQ(newestStampNs(odometry), last_stamp_ns) << "the last frame's odometry was not published";
  if (mode == "rgbd") {
    EXPECT_EQ(newestStampNs(imu_state), -1) << "rgbd mode publishes no rt/vifusion/imu_state";
  } else {
    // Every frame used its IMU samples (none refused, which would take the log's allocating path) and
    // the estimator's state went out for the last one.
    EXPECT_EQ(state.imu_issue_frames.load(), 0u) << "frames whose IMU samples were refused";
    dds::msg::ImuState last{};
    EXPECT_EQ(newestStampNs(imu_state, &last), last_stamp_ns)
        << "the last frame's rt/vifusion/imu_state was not published";
    // What went out is the estimator fed with the right samples: velocity and gravity near the truth.
    const double velocity_error_mps = (toEigen(last.velocity) - inertial->last_v_W_mps).norm();
    const double gravity_error_rad =
        std::acos(std::clamp(toEigen(last.gravity_direction).dot(inertial->down_W), -1.0, 1.0));
    std::printf(
        "rgbdi, last frame: velocity %.4f m/s off the true %.4f m/s (σ %.4f m/s along W x), gravity %.3f° off\n",
        velocity_error_mps, inertial->last_v_W_mps.norm(), std::sqrt(last.velocity_covariance[0]),
        gravity_error_rad * 180.0 / M_PI);
    EXPECT_LT(velocity_error_mps, 0.02);
    EXPECT_LT(gravity_error_rad, 1.0 * M_PI / 180.0);
  }
}

TEST(DaemonSteadyState, AllocatesNothingPerFrame) {
  const RigCalibration calibration = panCalibration();
  const std::vector<RgbdFrame> sequence = renderPan(calibration.camera);
  expectNoAllocationPerFrame(
      "rgbd", calibration, [&](std::size_t i) -> const RgbdFrame& { return pingPong(sequence, i); }, nullptr);
}

TEST(DaemonSteadyState, AllocatesNothingPerFrameInRgbdiMode) {
  const RigCalibration calibration = panCalibration();
  const InertialSequence sequence = renderInertialSequence(calibration, kFrames);
  expectNoAllocationPerFrame(
      "rgbdi", calibration, [&](std::size_t i) -> const RgbdFrame& { return sequence.frames[i]; }, &sequence);
}

}  // namespace
}  // namespace vifusion::daemon
