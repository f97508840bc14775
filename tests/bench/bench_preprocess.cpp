// Preprocessing and normal-equation reduction: GPU kernels vs their CPU references, per step, at
// 640×480 and 320×240, on a real 7-Scenes frame, on whatever device is picked (lavapipe in CI).
// JSON: bench_preprocess --benchmark_out=bench.json --benchmark_out_format=json
// Each GPU iteration is submit + wait of a pre-recorded command buffer (the real per-frame cost).

#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/preprocess/preprocess_cpu.hpp"
#include "vifusion/preprocess/preprocess_stage.hpp"
#include "vifusion/reduction/row_reducer.hpp"
#include "vifusion/test/seven_scenes_frame.hpp"

namespace vifusion {
namespace {

/// Everything one resolution needs, built once before timing.
struct Setup {
  test::SevenScenesFrame frame;
  std::unique_ptr<preprocess::PreprocessStage> stage;
  std::unique_ptr<RowReducer> reducer;
  std::unique_ptr<gpu::MemoryArena> arena;
  std::unique_ptr<preprocess::PreprocessCpu> cpu;
  uint32_t rows = 0;
};

gpu::GpuContext& context() {
  static const auto instance = gpu::GpuContext::create(gpu::GpuOptions{}.withEnvironment());
  return *instance;
}

/// The 640×480 frame, or every second pixel of it for 320×240.
test::SevenScenesFrame frameAt(int width) {
  test::SevenScenesFrame full = test::loadSevenScenesFrame(150);
  if (width == full.camera.width) return full;
  const int step = full.camera.width / width;
  test::SevenScenesFrame small{Image<std::uint16_t>(width, full.camera.height / step),
                               Image<preprocess::Rgb8>(width, full.camera.height / step), full.camera.atLevel(step / 2), full.T_W_C};
  for (int y = 0; y < small.depth_mm.height(); ++y) {
    for (int x = 0; x < width; ++x) {
      small.depth_mm(x, y) = full.depth_mm(step * x, step * y);
      small.rgb(x, y) = full.rgb(step * x, step * y);
    }
  }
  return small;
}

Setup& setupFor(int width) {
  static std::vector<std::unique_ptr<Setup>> setups;
  for (auto& setup : setups) {
    if (setup->frame.camera.width == width) return *setup;
  }
  auto setup = std::make_unique<Setup>();
  setup->frame = frameAt(width);
  preprocess::PreprocessOptions options;
  options.camera = setup->frame.camera;
  setup->rows = static_cast<uint32_t>(setup->frame.depth_mm.pixelCount());
  gpu::CapacityPlan plan;
  setup->stage = std::make_unique<preprocess::PreprocessStage>(context(), plan, options);
  RowReducerOptions reducer_options;
  reducer_options.max_rows = setup->rows;
  setup->reducer = std::make_unique<RowReducer>(context(), plan, reducer_options);
  setup->arena = gpu::MemoryArena::create(context(), plan);
  setup->stage->build(*setup->arena);
  setup->reducer->build(*setup->arena);
  setup->stage->upload(setup->frame.depth_mm.view(), setup->frame.rgb.view());
  setup->cpu = std::make_unique<preprocess::PreprocessCpu>(options);
  setup->cpu->setInput(setup->frame.depth_mm.view(), setup->frame.rgb.view());
  setup->cpu->run();
  // Point-to-plane rows J = [n, p × n] from the frame's own vertex and normal maps.
  const auto& level0 = setup->cpu->level(0);
  const std::span<ResidualRow> rows = setup->reducer->rows();
  for (uint32_t i = 0; i < setup->rows; ++i) {
    const Eigen::Vector3f p = level0.vertices.data()[i].head<3>();
    const Eigen::Vector3f n = level0.normals.data()[i].head<3>();
    const Eigen::Vector3f pxn = p.cross(n);
    rows[i] = {{n.x(), n.y(), n.z(), pxn.x(), pxn.y(), pxn.z()}, 0.001f, level0.normals.data()[i].w()};
  }
  setups.push_back(std::move(setup));
  return *setups.back();
}

void reportPixels(benchmark::State& state, const Setup& setup) {
  state.counters["pixels"] = static_cast<double>(setup.rows);
}

void gpuStep(benchmark::State& state, int width, int step_index) {
  Setup& setup = setupFor(width);
  auto sequence = gpu::CommandSequence::create(context(), "bench");
  sequence->record([&](gpu::CommandRecorder& recorder) {
    if (step_index < 0) {
      setup.stage->record(recorder);
    } else {
      setup.stage->recordStep(recorder, preprocess::kAllPreprocessSteps[step_index]);
    }
  });
  sequence->run();  // warm-up
  for (auto _ : state) sequence->run();
  reportPixels(state, setup);
}

void cpuStep(benchmark::State& state, int width, int step_index) {
  Setup& setup = setupFor(width);
  for (auto _ : state) {
    if (step_index < 0) {
      setup.cpu->run();
    } else {
      setup.cpu->runStep(preprocess::kAllPreprocessSteps[step_index]);
    }
  }
  reportPixels(state, setup);
}

void gpuReduction(benchmark::State& state, int width) {
  Setup& setup = setupFor(width);
  auto sequence = gpu::CommandSequence::create(context(), "bench.reduce");
  sequence->record([&](gpu::CommandRecorder& recorder) { setup.reducer->record(recorder, setup.rows); });
  sequence->run();
  for (auto _ : state) sequence->run();
  state.SetLabel(setup.reducer->usesSubgroups() ? "subgroup" : "shared memory");
  reportPixels(state, setup);
}

void cpuReduction(benchmark::State& state, int width) {
  Setup& setup = setupFor(width);
  for (auto _ : state) benchmark::DoNotOptimize(reduceRowsCpu(setup.reducer->rows().first(setup.rows)));
  reportPixels(state, setup);
}

void registerAll() {
  for (int width : {640, 320}) {
    const std::string size = width == 640 ? "640x480" : "320x240";
    for (int step = -1; step < static_cast<int>(std::size(preprocess::kAllPreprocessSteps)); ++step) {
      const std::string name = step < 0 ? "total" : preprocess::preprocessStepName(preprocess::kAllPreprocessSteps[step]);
      benchmark::RegisterBenchmark(("preprocess/" + name + "/gpu/" + size).c_str(), gpuStep, width, step)
          ->Unit(benchmark::kMillisecond)->UseRealTime();
      benchmark::RegisterBenchmark(("preprocess/" + name + "/cpu_reference/" + size).c_str(), cpuStep, width, step)
          ->Unit(benchmark::kMillisecond)->UseRealTime();
    }
    benchmark::RegisterBenchmark(("reduction/gpu/" + size).c_str(), gpuReduction, width)
        ->Unit(benchmark::kMillisecond)->UseRealTime();
    benchmark::RegisterBenchmark(("reduction/cpu_reference/" + size).c_str(), cpuReduction, width)
        ->Unit(benchmark::kMillisecond)->UseRealTime();
  }
}

}  // namespace
}  // namespace vifusion

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::AddCustomContext("device", vifusion::context().features().device_name);
  vifusion::registerAll();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
