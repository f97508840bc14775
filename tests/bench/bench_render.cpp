// Synthetic living-room rendering: frames per second of the ray caster, noise-free and with the
// ICL-NUIM sensor-noise model, at 640×480 and 320×240, on a view with furniture, walls and floor,
// with antialiased colour (the default) and point-sampled colour (one ray per pixel, the cost floor).
// items/s = frames/s. The goal is ≥ 20 frames/s noise-free at 640×480 on 2 cores.
// JSON: bench_render --benchmark_out=bench.json --benchmark_out_format=json

#include <benchmark/benchmark.h>

#include <cstdint>

#include "vifusion/core/image.hpp"
#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/scene/living_room.hpp"
#include "vifusion/scene/look_at.hpp"
#include "vifusion/scene/renderer.hpp"
#include "vifusion/scene/row_pool.hpp"
#include "vifusion/scene/sensor_noise.hpp"

namespace vifusion::scene {
namespace {

/// Pools built once: with every hardware thread (argument 0), and with only the calling thread (1),
/// whose CPU time is the per-frame cost that the multi-threaded run divides among the cores.
RowPool& pool(std::int64_t threads) {
  static RowPool all;
  static RowPool one(1);
  return threads == 1 ? one : all;
}

const LivingRoom& room() {
  static const LivingRoom instance;
  return instance;
}

/// ICL-NUIM intrinsics scaled to `width`; looking from the sofa side across the coffee table at the
/// bookshelf, cabinet and TV (a busy view: most pixels hit furniture or textured walls).
PinholeCamera cameraFor(int width) {
  const PinholeCamera full = PinholeCamera::create(640, 480, 481.2, -480.0, 319.5, 239.5);
  return width == 640 ? full : full.atLevel(1);
}

SE3d benchmarkPose() { return lookAt(Eigen::Vector3d(2.2, 1.6, 1.5), Eigen::Vector3d(-1.0, 0.6, -3.0)); }

/// Default options (antialiased = 1) or colour from the centre ray's point-sampled texture (0).
RenderOptions renderOptions(std::int64_t antialiased) {
  RenderOptions options;
  if (antialiased == 0) {
    options.filter_textures = false;
    options.edge_samples_per_axis = 1;
  }
  return options;
}

void renderClean(benchmark::State& state) {
  const PinholeCamera camera = cameraFor(static_cast<int>(state.range(0)));
  RowPool& threads = pool(state.range(1));
  const Renderer renderer(room(), threads, renderOptions(state.range(2)));
  Image<Rgb8> rgb(camera.width, camera.height);
  Image<std::uint16_t> depth(camera.width, camera.height);
  const SE3d T_W_C = benchmarkPose();
  for (auto _ : state) {
    renderer.render(T_W_C, camera, rgb.view(), depth.view());
    benchmark::DoNotOptimize(rgb.data());
    benchmark::DoNotOptimize(depth.data());
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["threads"] = threads.threadCount();
}

void renderNoisy(benchmark::State& state) {
  const PinholeCamera camera = cameraFor(static_cast<int>(state.range(0)));
  RowPool& threads = pool(state.range(1));
  const Renderer renderer(room(), threads, renderOptions(state.range(2)));
  SensorNoise noise(SensorNoiseOptions{}, threads);
  Image<Rgb8> rgb(camera.width, camera.height);
  Image<float> clean_depth_m(camera.width, camera.height);
  Image<std::uint16_t> depth(camera.width, camera.height);
  noise.reserve(camera.width, camera.height);
  const SE3d T_W_C = benchmarkPose();
  std::uint64_t frame = 0;
  for (auto _ : state) {
    renderer.render(T_W_C, camera, rgb.view(), clean_depth_m.view());
    noise.addDepthNoise(clean_depth_m.view(), depth.view(), frame);
    noise.addIntensityNoise(rgb.view(), frame);
    ++frame;
    benchmark::DoNotOptimize(rgb.data());
    benchmark::DoNotOptimize(depth.data());
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["threads"] = threads.threadCount();
}

// Arguments: image width [px], threads (0 = all hardware threads, 1 = the calling thread only),
// antialiased colour (1) or point-sampled (0). Real time, because the pool's workers do not count
// towards the calling thread's CPU time.
BENCHMARK(renderClean)
    ->ArgsProduct({{640, 320}, {0, 1}, {1, 0}})
    ->ArgNames({"width", "threads", "antialiased"})
    ->Name("render_clean")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(renderNoisy)
    ->ArgsProduct({{640, 320}, {0, 1}, {1, 0}})
    ->ArgNames({"width", "threads", "antialiased"})
    ->Name("render_noisy")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace vifusion::scene

BENCHMARK_MAIN();
