#include "gpu_self_check.hpp"

#include <Eigen/Geometry>
#include <chrono>
#include <cstdio>
#include <functional>

#include "synthetic_frame.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/preprocess/preprocess_cpu.hpp"
#include "vifusion/preprocess/preprocess_stage.hpp"
#include "vifusion/reduction/row_reducer.hpp"

namespace vifusion::cli {
namespace {

/// Mean wall time of `fn` over `repetitions` calls [ms].
double meanMs(int repetitions, const std::function<void()>& fn) {
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < repetitions; ++i) fn();
  const std::chrono::duration<double, std::milli> elapsed = std::chrono::steady_clock::now() - start;
  return elapsed.count() / repetitions;
}

double mebibytes(uint64_t bytes) { return static_cast<double>(bytes) / (1024.0 * 1024.0); }

/// Largest difference over pixels valid in both images, and how many pixels differ in validity.
struct Agreement {
  double max_abs = 0.0;
  long validity_mismatches = 0;
};

Agreement compareVec4(const preprocess::VertexPixel* gpu, const Image<preprocess::VertexPixel>& cpu) {
  Agreement a;
  for (std::size_t i = 0; i < cpu.pixelCount(); ++i) {
    const bool gpu_valid = !gpu[i].isZero(0.0);
    const bool cpu_valid = !cpu.data()[i].isZero(0.0);
    if (gpu_valid != cpu_valid) {
      ++a.validity_mismatches;
    } else if (gpu_valid) {
      a.max_abs = std::max(a.max_abs, static_cast<double>((gpu[i] - cpu.data()[i]).cwiseAbs().maxCoeff()));
    }
  }
  return a;
}

}  // namespace

int runGpuSelfCheck(const SelfCheckOptions& options) {
  if (options.frames < 1) throw Error("--frames must be at least 1");
  gpu::GpuOptions gpu_options;
  gpu_options.device = options.device;
  const auto context = gpu::GpuContext::create(gpu_options.withEnvironment());
  const gpu::GpuFeatures& f = context->features();
  std::printf("vifusion GPU self-check\n");
  std::printf("device   %s (%s), Vulkan %u.%u, %s\n", f.device_name.c_str(), gpu::deviceTypeName(f.device_type),
              VK_API_VERSION_MAJOR(f.api_version), VK_API_VERSION_MINOR(f.api_version), f.driver_info.c_str());
  std::printf("features subgroup size %u, subgroup arithmetic %s, fp64 %s, float atomics %s, unified memory %s\n",
              f.subgroup_size, f.subgroup_arithmetic ? "yes" : "no", f.float64 ? "yes" : "no",
              f.float32_atomic_add ? "yes" : "no", f.unified_memory ? "yes" : "no");

  const SyntheticFrame frame = renderSyntheticFrame(options.width, options.height);
  preprocess::PreprocessOptions preprocess_options;
  preprocess_options.camera = frame.camera;
  const uint32_t pixel_count = static_cast<uint32_t>(frame.camera.width * frame.camera.height);

  gpu::CapacityPlan plan;
  preprocess::PreprocessStage stage(*context, plan, preprocess_options);
  RowReducerOptions reducer_options;
  reducer_options.max_rows = pixel_count;
  RowReducer reducer(*context, plan, reducer_options);
  // Level-0 vertices and normals are copied out to compare them with the CPU reference.
  const auto vertices_out =
      plan.addBuffer("selfcheck.vertices", pixel_count * sizeof(preprocess::VertexPixel), gpu::MemoryUse::Readback);
  const auto normals_out =
      plan.addBuffer("selfcheck.normals", pixel_count * sizeof(preprocess::NormalPixel), gpu::MemoryUse::Readback);
  const auto arena = gpu::MemoryArena::create(*context, plan);
  stage.build(*arena);
  reducer.build(*arena);
  std::printf("arena    %.1f MiB in %zu allocation(s) for %zu buffers\n", mebibytes(arena->allocatedBytes()),
              arena->blocks().size(), plan.buffers().size());

  auto full = gpu::CommandSequence::create(*context, "preprocess");
  full->record([&](gpu::CommandRecorder& recorder) {
    stage.record(recorder);
    const preprocess::LevelBuffers& level0 = stage.level(0);
    recorder.copyBuffer(arena->buffer(level0.vertices), arena->buffer(vertices_out), arena->buffer(vertices_out).bytes);
    recorder.copyBuffer(arena->buffer(level0.normals), arena->buffer(normals_out), arena->buffer(normals_out).bytes);
    recorder.hostReadBarrier();
  });
  stage.upload(frame.depth_mm.view(), frame.rgb.view());
  full->run();

  preprocess::PreprocessCpu cpu(preprocess_options);
  cpu.setInput(frame.depth_mm.view(), frame.rgb.view());

  std::printf("\nframe %dx%d, %d levels, mean of %d runs\n", frame.camera.width, frame.camera.height,
              preprocess_options.levels, options.frames);
  std::printf("%-26s %12s %12s %8s\n", "step", "GPU ms", "CPU ref ms", "ratio");
  double gpu_total = 0.0;
  double cpu_total = 0.0;
  for (preprocess::PreprocessStep step : preprocess::kAllPreprocessSteps) {
    auto sequence = gpu::CommandSequence::create(*context, preprocess::preprocessStepName(step));
    sequence->record([&](gpu::CommandRecorder& recorder) { stage.recordStep(recorder, step); });
    const double gpu_ms = meanMs(options.frames, [&] { sequence->run(); });
    const double cpu_ms = meanMs(options.frames, [&] { cpu.runStep(step); });
    gpu_total += gpu_ms;
    cpu_total += cpu_ms;
    std::printf("%-26s %12.2f %12.2f %8.2f\n", preprocess::preprocessStepName(step), gpu_ms, cpu_ms, cpu_ms / gpu_ms);
  }
  const double upload_ms = meanMs(options.frames, [&] { stage.upload(frame.depth_mm.view(), frame.rgb.view()); });
  std::printf("%-26s %12.2f %12.2f %8.2f\n", "preprocess total", gpu_total, cpu_total, cpu_total / gpu_total);
  std::printf("%-26s %12.2f\n", "upload (host packing)", upload_ms);

  // Point-to-plane rows from the CPU vertex and normal maps: J = [n, p × n], small residuals.
  const auto& level0 = cpu.level(0);
  const std::span<ResidualRow> rows = reducer.rows();
  for (uint32_t i = 0; i < pixel_count; ++i) {
    const Eigen::Vector3f p = level0.vertices.data()[i].head<3>();
    const Eigen::Vector3f n = level0.normals.data()[i].head<3>();
    const Eigen::Vector3f pxn = p.cross(n);
    rows[i] = {{n.x(), n.y(), n.z(), pxn.x(), pxn.y(), pxn.z()},
               0.001f * std::sin(0.01f * i),
               level0.normals.data()[i].w() > 0.0f ? 1.0f : 0.0f};
  }
  auto reduce = gpu::CommandSequence::create(*context, "reduce");
  reduce->record([&](gpu::CommandRecorder& recorder) { reducer.record(recorder, pixel_count); });
  const double reduce_gpu_ms = meanMs(options.frames, [&] { reduce->run(); });
  NormalEquations6 reference;
  const double reduce_cpu_ms = meanMs(options.frames, [&] { reference = reduceRowsCpu(rows); });
  const NormalEquations6 reduced = reducer.result();
  const double reduction_error = (reduced.H - reference.H).norm() / reference.H.norm();
  std::printf("%-26s %12.2f %12.2f %8.2f  (%s, %u rows)\n", "normal-equation reduction", reduce_gpu_ms, reduce_cpu_ms,
              reduce_cpu_ms / reduce_gpu_ms, reducer.usesSubgroups() ? "subgroup" : "shared memory", pixel_count);

  // Agreement of the full chains (GPU vs CPU reference) on the level-0 outputs.
  cpu.run();
  const Agreement vertices =
      compareVec4(arena->buffer(vertices_out).hostSpan<preprocess::VertexPixel>().data(), level0.vertices);
  const Agreement normals =
      compareVec4(arena->buffer(normals_out).hostSpan<preprocess::NormalPixel>().data(), level0.normals);
  std::printf("\nagreement with the CPU reference\n");
  std::printf("vertices   max |Δ| %.2e m, validity mismatches %ld\n", vertices.max_abs, vertices.validity_mismatches);
  std::printf("normals    max |Δ| %.2e,   validity mismatches %ld\n", normals.max_abs, normals.validity_mismatches);
  std::printf("reduction  relative |ΔH| %.2e, inliers %.0f (CPU %.0f)\n", reduction_error, reduced.inliers,
              reference.inliers);

  // Tolerances of whole chains: the bilateral filter's exp differs by ~1e-6 m between devices and
  // the normals' forward differences over 2–4 mm amplify that, hence 2e-3 on normals here while
  // tests/gpu, comparing each kernel on identical input, holds them to 1e-4.
  const bool ok = vertices.max_abs <= 1e-5 && normals.max_abs <= 2e-3 && reduction_error <= 1e-5 &&
                  vertices.validity_mismatches <= static_cast<long>(pixel_count / 10000) &&
                  normals.validity_mismatches <= static_cast<long>(pixel_count / 10000) &&
                  reduced.inliers == reference.inliers;
  std::printf("\nresult     %s\n", ok ? "PASS: GPU kernels agree with their CPU references" : "FAIL: see above");
  return ok ? 0 : 1;
}

}  // namespace vifusion::cli
