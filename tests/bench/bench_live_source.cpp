// CPU cost of the live ZR300 source's driver threads per second of streaming (issue 17): the camera thread
// (dequeue, DS4 metadata, Z16 copy into the padded image, YUYV → RGB, pairing, stamping) and the motion-module
// thread (transfer decode, clock mapping, scaling, merge), streaming a scripted camera (tests/live) for 10 s of
// camera time at each preset while a consumer takes every frame and its IMU window. The scripted device makes
// its frames on the polling thread; that time is measured and subtracted (producerCpuNs()). Counters:
// driver_cpu_ms_per_s (both threads, per second of camera time), frames.

#include <benchmark/benchmark.h>

#include "../live/scripted_camera.hpp"
#include "vifusion/zr300/zr300_source.hpp"

namespace vifusion::live_test {
namespace {

constexpr std::int64_t kStartNs = 1'000'000'000'000;
constexpr std::int64_t kImuPeriodNs = 5'000'000;
constexpr std::int64_t kImuLeadNs = 2'500'000'000;
constexpr double kSeconds = 10.0;

CameraScript benchScript(zr300::StreamPreset preset) {
  CameraScript script;
  script.preset = preset;
  const std::int64_t period_ns = 1'000'000'000 / preset.fps;
  for (int k = 0; k < static_cast<int>(kSeconds * preset.fps); ++k) {
    script.frame_t_ns.push_back(kStartNs + k * period_ns / 1000 * 1000);
  }
  script.depth = [](int k, ImageView<std::uint16_t> inner) {
    for (int y = 0; y < inner.height; ++y) {
      for (int x = 0; x < inner.width; ++x) inner(x, y) = static_cast<std::uint16_t>(1000 + ((x + y + k) & 1023));
    }
  };
  script.colour = [](int k, ImageView<Rgb8> rgb) {
    for (int y = 0; y < rgb.height; ++y) {
      for (int x = 0; x < rgb.width; ++x)
        rgb(x, y) = {static_cast<std::uint8_t>(x + k), static_cast<std::uint8_t>(y), 80};
    }
  };
  for (std::int64_t t = kStartNs - kImuLeadNs; t <= script.frame_t_ns.back() + 100'000'000; t += kImuPeriodNs) {
    script.imu.push_back({t, {10, -20, 30}, {0, 0, 512 << 4}});
  }
  return script;
}

void BM_LiveSourceDriverCpu(benchmark::State& state) {
  const zr300::StreamPreset preset = zr300::kPresets[state.range(0)];
  double cpu_ms_per_s = 0.0;
  std::size_t frames = 0;
  for (auto _ : state) {
    CameraScript script = benchScript(preset);
    const std::size_t total = script.frame_t_ns.size();
    auto camera = std::make_unique<ScriptedCamera>(std::move(script));
    ScriptedCamera& scripted = *camera;
    RigCalibration calibration;
    calibration.camera = PinholeCamera::create(preset.width_px, preset.height_px, 1.0 * preset.width_px,
                                               1.0 * preset.width_px, 0.5 * preset.width_px, 0.5 * preset.height_px);
    calibration.depth_camera = DepthCameraCalibration{calibration.camera, SE3d()};
    zr300::Zr300Options options;
    options.preset = preset;
    zr300::Zr300Source source(std::move(camera), {}, calibration, options);
    RgbdFrame frame;
    for (frames = 0; frames < total && source.nextFrame(frame); ++frames) {
      source.imuFeed()->samplesThrough(frame.t_ns);
    }
    const double driver_ms = static_cast<double>(source.driverCpuNs() - scripted.producerCpuNs()) * 1e-6;
    cpu_ms_per_s = driver_ms / kSeconds;
  }
  state.counters["driver_cpu_ms_per_s"] = cpu_ms_per_s;
  state.counters["frames"] = static_cast<double>(frames);
  state.SetLabel(std::to_string(preset.width_px) + "x" + std::to_string(preset.height_px) + "@" +
                 std::to_string(preset.fps));
}
BENCHMARK(BM_LiveSourceDriverCpu)->DenseRange(0, 2)->Iterations(1)->Unit(benchmark::kSecond);

}  // namespace
}  // namespace vifusion::live_test

BENCHMARK_MAIN();
