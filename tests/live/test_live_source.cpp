// The live ZR300 source end to end on a scripted camera (scripted_camera.hpp): 30 s of depth, colour and IMU
// streamed through the real V4L2 stream code, the motion-module driver, the device→host clock mapping and the
// frame assembly must come out as exactly the frames, IMU samples and timestamps the script holds; and an
// unplug/replug mid-stream loses nothing already delivered and resumes streaming by itself.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>

#include "scripted_camera.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/discovery/discovery_error.hpp"
#include "vifusion/test/counting_allocations.hpp"
#include "vifusion/zr300/zr300_source.hpp"

namespace vifusion::live_test {
namespace {

constexpr std::int64_t kT0Ns = 2'000'000'000'000;  // first frame at 2000 s of uptime
constexpr std::int64_t kFramePeriodNs = 33'333'333;
constexpr std::int64_t kImuPeriodNs = 5'000'000;  // 200 Hz
/// IMU before the first frame: the clock mapping's 2 s warm-up plus the estimator's gravity window.
constexpr std::int64_t kImuLeadNs = 2'500'000'000;
constexpr std::int64_t kGravityWindowNs = 200'000'000;

std::uint16_t depthAt(int k, int x, int y) { return static_cast<std::uint16_t>(1 + (k * 7 + x * 3 + y * 11) % 8000); }
Rgb8 colourAt(int k, int x, int y) {
  return {static_cast<std::uint8_t>(k + x), static_cast<std::uint8_t>(2 * y + k), static_cast<std::uint8_t>(x * y)};
}

/// A procedural script: `seconds` of frames at 320×240, 30 Hz, IMU at 200 Hz from kImuLeadNs before.
CameraScript proceduralScript(double seconds) {
  CameraScript script;
  const auto frames = static_cast<int>(seconds * 30.0);
  for (int k = 0; k < frames; ++k) script.frame_t_ns.push_back(kT0Ns + k * kFramePeriodNs / 1000 * 1000);
  script.depth = [](int k, ImageView<std::uint16_t> inner) {
    for (int y = 0; y < inner.height; ++y) {
      for (int x = 0; x < inner.width; ++x) inner(x, y) = depthAt(k, x, y);
    }
  };
  script.colour = [](int k, ImageView<Rgb8> rgb) {
    for (int y = 0; y < rgb.height; ++y) {
      for (int x = 0; x < rgb.width; ++x) rgb(x, y) = colourAt(k, x, y);
    }
  };
  for (std::int64_t t = kT0Ns - kImuLeadNs, i = 0; t <= script.frame_t_ns.back() + 100'000'000;
       t += kImuPeriodNs, ++i) {
    RawImu raw;
    raw.t_ns = t;
    raw.gyro = {static_cast<std::int16_t>(i % 200 - 100), static_cast<std::int16_t>(-3 * (i % 50)), 700};
    raw.accel = {static_cast<std::int16_t>((i % 64) << 4), static_cast<std::int16_t>(-(i % 16) << 4),
                 static_cast<std::int16_t>(512 << 4)};
    script.imu.push_back(raw);
  }
  return script;
}

RigCalibration calibrationFor(const CameraScript& script) {
  RigCalibration calibration;
  calibration.camera =
      PinholeCamera::create(script.preset.width_px, script.preset.height_px, 270.0, 270.0, 159.5, 119.5);
  calibration.depth_camera = DepthCameraCalibration{calibration.camera, SE3d()};
  return calibration;
}

/// The live source on a scripted camera playing `script`, with default options at the script's preset.
struct ScriptedSource {
  explicit ScriptedSource(CameraScript script) {
    auto owned = std::make_unique<ScriptedCamera>(std::move(script));
    camera = owned.get();
    zr300::Zr300Options options;
    options.preset = camera->script().preset;
    source = std::make_unique<zr300::Zr300Source>(std::move(owned), discovery::Zr300SourceSpec{},
                                                  calibrationFor(camera->script()), options);
  }
  ScriptedCamera* camera = nullptr;  ///< owned by the source
  std::unique_ptr<zr300::Zr300Source> source;
};

/// Every distinct IMU sample the feed handed out, in order (windows overlap).
class ImuCollector {
 public:
  void add(std::span<const ImuSample> window) {
    for (const ImuSample& sample : window) {
      if (samples_.empty() || sample.t_ns > samples_.back().t_ns) samples_.push_back(sample);
    }
  }
  const std::vector<ImuSample>& samples() const { return samples_; }

 private:
  std::vector<ImuSample> samples_;
};

TEST(LiveSource, ThirtySecondsComeOutAsScriptedFramesImuAndTimes) {
  CameraScript script = proceduralScript(30.0);
  const std::vector<std::int64_t> frame_t = script.frame_t_ns;
  const std::vector<RawImu> imu = script.imu;
  ScriptedSource scripted_source(std::move(script));
  ScriptedCamera& scripted = *scripted_source.camera;
  zr300::Zr300Source& source = *scripted_source.source;
  EXPECT_DOUBLE_EQ(source.calibration().depth_scale_m, 1.0 / 5000.0);
  ASSERT_NE(source.imuFeed(), nullptr);

  const int width = scripted.script().preset.width_px;
  const int height = scripted.script().preset.height_px;
  Image<Rgb8> script_rgb(width, height), expected(width, height);
  RgbdFrame frame;
  ImuCollector collected;
  std::int64_t worst_time_error_ns = 0, worst_kernel_error_ns = 0;
  int depth_mismatches = 0, rgb_mismatches = 0, timing_mismatches = 0;
  for (std::size_t k = 0; k < frame_t.size(); ++k) {
    ASSERT_TRUE(source.nextFrame(frame)) << "frame " << k;
    ASSERT_EQ(frame.index, static_cast<std::int64_t>(k));
    worst_time_error_ns = std::max(worst_time_error_ns, std::abs(frame.t_ns - frame_t[k]));
    // The device's view of the frame's time goes with it (what recordings keep): its DS4 counter, the event
    // that stamped it on both clocks, and the kernel's own time of the buffer.
    const FrameTiming& timing = frame.timing;
    timing_mismatches += timing.device_frame_number == kFirstFrameCounter + static_cast<std::uint32_t>(k) &&
                                 timing.stamped_by_device_event && timing.device_event_ns == frame.t_ns &&
                                 timing.device_event_clock_ns > 0
                             ? 0
                             : 1;
    worst_kernel_error_ns = std::max(worst_kernel_error_ns, std::abs(timing.kernel_mid_exposure_ns - frame_t[k]));
    collected.add(source.imuFeed()->samplesThrough(frame.t_ns));
    const int ki = static_cast<int>(k);
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const bool padding = x < zr300::kDepthPaddingPx || x >= width - zr300::kDepthPaddingPx ||
                             y < zr300::kDepthPaddingPx || y >= height - zr300::kDepthPaddingPx;
        const std::uint16_t want = padding ? 0 : depthAt(ki, x - zr300::kDepthPaddingPx, y - zr300::kDepthPaddingPx);
        depth_mismatches += frame.depth(x, y) != want ? 1 : 0;
      }
    }
    scripted.script().colour(ki, script_rgb.view());
    expectedRgb(script_rgb.view(), kFirstFrameCounter + static_cast<std::uint32_t>(k), expected.view());
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) rgb_mismatches += frame.rgb(x, y) == expected(x, y) ? 0 : 1;
    }
  }
  EXPECT_LE(worst_time_error_ns, 1000) << "frame times within 1 µs of the motion module's events";
  EXPECT_EQ(timing_mismatches, 0) << "frames whose FrameTiming does not say how they were stamped";
  EXPECT_LT(worst_kernel_error_ns, 10 * kNsPerMillisecond) << "kernel mid-exposure times";
  EXPECT_EQ(depth_mismatches, 0);
  EXPECT_EQ(rgb_mismatches, 0);

  // Every IMU sample from the estimator's gravity window before the first frame through the last frame,
  // with its scripted time and reading.
  std::size_t first = 0;
  while (imu[first].t_ns < frame_t.front() - kGravityWindowNs) ++first;
  const std::vector<ImuSample>& got = collected.samples();
  const auto start =
      std::find_if(got.begin(), got.end(), [&](const ImuSample& s) { return s.t_ns >= imu[first].t_ns; });
  ASSERT_NE(start, got.end());
  std::size_t compared = 0;
  std::int64_t worst_imu_time_error_ns = 0;
  double worst_value_error = 0.0;
  for (auto it = start; it != got.end() && first + compared < imu.size(); ++it, ++compared) {
    const ImuSample want = toImuSample(imu[first + compared]);
    worst_imu_time_error_ns = std::max(worst_imu_time_error_ns, std::abs(it->t_ns - want.t_ns));
    worst_value_error = std::max({worst_value_error, (it->gyro_rad_s - want.gyro_rad_s).cwiseAbs().maxCoeff(),
                                  (it->accel_mps2 - want.accel_mps2).cwiseAbs().maxCoeff()});
  }
  EXPECT_EQ(start->t_ns, imu[first].t_ns);
  EXPECT_GE(got.back().t_ns, frame_t.back());
  EXPECT_GT(compared, static_cast<std::size_t>(30 * 200));
  EXPECT_LE(worst_imu_time_error_ns, 1000);
  EXPECT_LE(worst_value_error, 1e-12);

  const zr300::Zr300Stats stats = source.stats();
  EXPECT_EQ(stats.frames, frame_t.size());
  EXPECT_EQ(stats.event_timestamps, frame_t.size());
  EXPECT_EQ(stats.kernel_timestamps, 0u);
  EXPECT_EQ(stats.unpaired_depth + stats.unpaired_colour + stats.rejected_frames, 0u);
  EXPECT_EQ(stats.depth_dropped + stats.colour_dropped, 0);
  EXPECT_EQ(stats.motion.imu_overruns, 0u);
  EXPECT_NEAR(stats.motion.clock_skew_ppm, 0.0, 1e-3);
  EXPECT_EQ(source.liveImuFeed()->stats().late_frames, 0u);
  std::printf("30 s scripted: %zu frames, %zu IMU samples compared, worst frame time error %lld ns, IMU %lld ns\n",
              frame_t.size(), compared, static_cast<long long>(worst_time_error_ns),
              static_cast<long long>(worst_imu_time_error_ns));
}

TEST(LiveSource, UnplugAndReplugLoseNothingDeliveredAndStreamingResumes) {
  CameraScript script = proceduralScript(8.0);
  const std::int64_t unplug_ns = kT0Ns + 3 * kNsPerSecond;
  const std::int64_t replug_ns = kT0Ns + 5 * kNsPerSecond;
  script.unplug_at_ns = unplug_ns;
  script.replug_at_ns = replug_ns;
  const std::vector<std::int64_t> frame_t = script.frame_t_ns;
  ScriptedSource scripted_source(std::move(script));
  zr300::Zr300Source& source = *scripted_source.source;

  RgbdFrame frame;
  std::vector<std::int64_t> times;
  while (times.empty() || times.back() < frame_t.back() - kFramePeriodNs) {
    ASSERT_TRUE(source.nextFrame(frame));
    if (!times.empty()) {
      ASSERT_GT(frame.t_ns, times.back());
    }
    times.push_back(frame.t_ns);
    source.imuFeed()->samplesThrough(frame.t_ns);
  }
  // Every frame whose buffer completed before the unplug was delivered.
  std::size_t before = 0;
  while (before < times.size() && times[before] < unplug_ns) ++before;
  std::size_t scripted_before = 0;
  while (frame_t[scripted_before] + kArrivalDelayNs < unplug_ns) ++scripted_before;
  EXPECT_EQ(before, scripted_before);
  ASSERT_LT(before, times.size());
  const double resumed_after_s = nsToSeconds(times[before] - replug_ns);
  EXPECT_GE(resumed_after_s, -0.01);
  EXPECT_LE(resumed_after_s, 0.5) << "first frame after the camera came back (its hotplug event ends the wait)";
  const zr300::Zr300Stats stats = source.stats();
  EXPECT_TRUE(stats.camera_present);
  EXPECT_EQ(stats.unplugs, 1u);
  EXPECT_EQ(stats.reopens, 1u);
  EXPECT_FALSE(source.lastProblem().empty());
  std::printf("unplug at 3 s, replug at 5 s: %zu frames before, first frame %.3f s after the replug, %zu in all\n",
              before, resumed_after_s, times.size());
}

TEST(LiveSource, SteadyStreamingAllocatesNothing) {
  // The whole per-frame path of the live source: the camera thread (V4L2 dequeue, metadata, conversion,
  // pairing, event matching), the motion-module thread (decode, clock mapping, merge) and the consumer's
  // nextFrame() and IMU window, with the scripted devices on the same threads. Heap allocations in the whole
  // process are counted over 200 frames after a warm-up of 100 (the recycled ring slots are sized then).
  CameraScript script = proceduralScript(12.0);
  ScriptedSource scripted_source(std::move(script));
  zr300::Zr300Source& source = *scripted_source.source;
  RgbdFrame frame;
  constexpr int kWarmUp = 100;
  constexpr int kMeasured = 200;
  std::uint64_t before = 0;
  for (int k = 0; k < kWarmUp + kMeasured; ++k) {
    if (k == kWarmUp) before = test::heapAllocationCount();
    ASSERT_TRUE(source.nextFrame(frame));
    source.imuFeed()->samplesThrough(frame.t_ns);
  }
  const std::uint64_t allocations = test::heapAllocationCount() - before;
  EXPECT_EQ(allocations, 0u) << "heap allocations in " << kMeasured << " frames of live streaming";
  EXPECT_EQ(source.stats().kernel_timestamps, 0u);
}

TEST(LiveSource, AnAbsentCameraIsADiscoveryErrorAtOnce) {
  CameraScript script = proceduralScript(1.0);
  script.unplug_at_ns = 0;  // unplugged from the start
  zr300::Zr300Options options;
  options.preset = script.preset;
  const RigCalibration calibration = calibrationFor(script);
  EXPECT_THROW(zr300::Zr300Source(std::make_unique<ScriptedCamera>(std::move(script)), {}, calibration, options),
               discovery::DiscoveryError);
}

TEST(LiveSource, ACalibrationForAnotherImageSizeIsRefused) {
  CameraScript script = proceduralScript(1.0);
  zr300::Zr300Options options;
  options.preset = script.preset;
  RigCalibration calibration = calibrationFor(script);
  calibration.camera = PinholeCamera::create(640, 480, 500, 500, 319.5, 239.5);
  try {
    zr300::Zr300Source source(std::make_unique<ScriptedCamera>(std::move(script)), {}, calibration, options);
    FAIL() << "accepted a 640x480 calibration for a 320x240 stream";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("640x480"), std::string::npos) << error.what();
  }
}

// Without the depth camera's calibration the live source cannot register depth to colour; it refuses to start
// rather than pair every colour pixel with the depth of a point beside it.
TEST(LiveSource, ACalibrationWithoutTheDepthCameraIsRefused) {
  CameraScript script = proceduralScript(1.0);
  zr300::Zr300Options options;
  options.preset = script.preset;
  RigCalibration calibration = calibrationFor(script);
  calibration.depth_camera.reset();
  try {
    zr300::Zr300Source source(std::make_unique<ScriptedCamera>(std::move(script)), {}, calibration, options);
    FAIL() << "accepted a calibration without cam1";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("cam1"), std::string::npos) << error.what();
  }
  script = proceduralScript(1.0);
  calibration = calibrationFor(script);
  calibration.depth_camera->camera = PinholeCamera::create(640, 480, 500, 500, 319.5, 239.5);
  try {
    zr300::Zr300Source source(std::make_unique<ScriptedCamera>(std::move(script)), {}, calibration, options);
    FAIL() << "accepted a 640x480 depth camera for a 320x240 stream";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("depth camera (cam1) is for 640x480"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace vifusion::live_test
