// The whole RGB-D pipeline (slam::Slam: preprocessing, frame-to-model tracking, fusion, map upkeep
// and prediction) on the synthetic living room, at 640×480 and 320×240, beside two peers on the same
// frames: OpenCV's frame-to-frame cv::rgbd::RgbdICPOdometry and Open3D's frame-to-model tensor dense
// SLAM, with the ATE of all three against the simulator's ground truth, so that speed is never compared
// at broken accuracy. The goals (not tests): ≥ 15 frames/s at 640×480 and ≥ 30 at 320×240 on
// 2 cores via lavapipe.
//
//   bench_rgbd_slam [--frames=90] [--sizes=640x480,320x240] [--data_dir=DIR] [--vifusion=PATH]
//                   [--noise=1] [--photometric=1] [--opencv=1] [--open3d=1] [--mode=rgbd|rgbdi]
//                   [--steps=1] [--trajectory_dir=DIR]
//                   --benchmark_out=slam.json --benchmark_out_format=json
//
// The sequence (`vifusion sim --preset living_room_0`, the first `frames` frames at each size, with
// the simulator's sensor noise unless --noise=0) is generated once into --data_dir and reused; every
// frame is decoded into memory before timing. --photometric=0 tracks with ICP only; --trajectory_dir
// writes the estimates as TUM files. --mode=rgbdi runs SlamMode::kRgbdInertial with the sequence's whole
// IMU stream given with every frame (as `vifusion run` does); the peers use the camera only.
// Entries, one per size:
//   rgbd_slam/living_room_0/WxH (rgbd_slam_rgbdi/… with --mode=rgbdi)   one iteration per frame after
//       the first (which defines W, starts the map and warms up); real_time = wall time per frame.
//       Counters: ms_preprocess, ms_tracking, ms_mapping, ms_total (mean per timed frame), fps,
//       gn_iterations, ms_per_gn_iteration, lost_frames, surfels (at the end), map_overflow,
//       arena_bytes, ate_m (all frames);
//       opencv_ms, opencv_ate_m, opencv_failed_frames, opencv_threads; ratio = ms_total/opencv_ms,
//       ratio_odometry = (ms_preprocess + ms_tracking)/opencv_ms; open3d_ms, open3d_ate_m,
//       open3d_failed_frames, open3d_threads, ratio_open3d = ms_total/open3d_ms; goal_fps and goal_met (1/0).
//       cpu_ms_total: process CPU time per frame (lavapipe's threads included), for A/B runs on a
//       shared machine, where wall time follows the other load.
//   rgbd_slam_steps/living_room_0/WxH   (rgbd whatever --mode: a kernel profile) the same frames
//       through every kernel of the pipeline, one step per submission (each step's wall time includes
//       a submit and a wait, ≈ 20 µs on lavapipe, so the steps add up to a little more than the fused
//       per-frame sequences), fused at the ground-truth poses: ms_upload, ms_pre_<step>,
//       ms_fusion_<step>, ms_map_cleanup,
//       ms_map_compaction, ms_map_prediction, ms_reference_copy, ms_reference_gradients, and the
//       tracking terms per level summed over the frame's Gauss-Newton iterations
//       (ms_track_{icp,photometric}_l<l>, gn_iterations_l<l>); each with its CPU time (cpu_<name>).
//       The native-loop comparison (native_loops.hpp): one level-0 evaluation of each term at the
//       frame's final pose on the GPU (gpu_<term>_l0_ms) and as a plain C++ loop over read-back
//       copies of the same buffers on 1 and 2 threads (native_<term>_l0_ms_{1t,2t}), medians of 3;
//       ratio_<term>_l0_{1t,2t} = GPU / native wall time, ratio_cpu_<term>_l0 = GPU CPU time /
//       native 1-thread CPU time; native_<term>_l0_inliers_vs_gpu checks that both did the same work.
//       The model prediction likewise against its CPU references every 10th frame
//       (gpu_prediction_ms, native_prediction_ms_1t, ratio_prediction_1t, ratio_cpu_prediction,
//       native_prediction_ids_vs_gpu).

#include <benchmark/benchmark.h>

#include <cstdio>
#include <exception>
#include <fstream>
#include <opencv2/core.hpp>
#include <span>
#include <string>
#include <vector>

#include "bench_options.hpp"
#include "bench_sequence.hpp"
#include "open3d_slam.hpp"
#include "opencv_odometry.hpp"
#include "rgbd_slam_steps.hpp"
#include "timing.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/eval/metrics.hpp"
#include "vifusion/slam/slam.hpp"

namespace vifusion::bench {
namespace {

double goalFps(const Size& size) { return size.width >= 640 ? 15.0 : 30.0; }

void rgbdSlam(benchmark::State& state, Size size) {
  const Sequence& sequence = sequenceFor(size);
  slam::SlamOptions slam_options;  // defaults, as `vifusion run`
  slam_options.tracker.use_photometric = options().photometric;
  slam_options.mode = slam::slamModeFromName(options().mode);
  const bool inertial = slam_options.mode != slam::SlamMode::kRgbd;
  if (inertial && sequence.imu.empty())
    throw Error("--mode=" + options().mode + ": " + sequence.describe + " has no IMU");
  // The whole stream with every frame, as RecordedImuFeed: Slam finds each frame's part by binary search.
  const std::span<const ImuSample> imu =
      inertial ? std::span<const ImuSample>(sequence.imu) : std::span<const ImuSample>();
  slam::Slam pipeline(context(), sequence.calibration, slam_options);
  std::vector<eval::StampedPose> trajectory;
  trajectory.reserve(sequence.frames.size());
  // Frame 0 defines W and only starts the map (no tracking): it is the warm-up, not timed.
  trajectory.push_back({sequence.frames[0].t_ns, pipeline.process(sequence.frames[0], imu).T_W_C});

  double preprocess_ms = 0.0, tracking_ms = 0.0, mapping_ms = 0.0, iterations = 0.0;
  int lost = 0;
  slam::FrameResult last;
  std::size_t next = 1;
  double cpu_ms = 0.0;
  for (auto _ : state) {
    const double cpu_start = processCpuMs();
    last = pipeline.process(sequence.frames[next++], imu);
    cpu_ms += processCpuMs() - cpu_start;
    trajectory.push_back({last.t_ns, last.T_W_C});
    preprocess_ms += last.preprocess_ms;
    tracking_ms += last.tracking_ms;
    mapping_ms += last.mapping_ms;
    iterations += last.iterations;
    lost += last.lost() ? 1 : 0;
  }

  const double timed = static_cast<double>(next - 1);
  const double ms_total = (preprocess_ms + tracking_ms + mapping_ms) / timed;
  auto& c = state.counters;
  c["frames"] = timed;
  c["ms_preprocess"] = preprocess_ms / timed;
  c["ms_tracking"] = tracking_ms / timed;
  c["ms_mapping"] = mapping_ms / timed;
  c["ms_total"] = ms_total;
  c["fps"] = 1000.0 / ms_total;
  c["cpu_ms_total"] = cpu_ms / timed;
  c["gn_iterations"] = iterations / timed;
  c["ms_per_gn_iteration"] = iterations > 0.0 ? tracking_ms / iterations : 0.0;
  c["lost_frames"] = lost;
  c["surfels"] = last.surfels;
  c["map_overflow"] = last.map_overflow;
  c["arena_bytes"] = static_cast<double>(pipeline.arenaBytes());
  c["ate_m"] = eval::ate(sequence.ground_truth, trajectory).rmse_m;
  writeTrajectory("vifusion_" + (inertial ? options().mode + "_" : std::string()) + size.name(), trajectory);
  c["goal_fps"] = goalFps(size);
  c["goal_met"] = 1000.0 / ms_total >= goalFps(size) ? 1.0 : 0.0;
  if (options().opencv) {
    const OpenCvRun opencv = runOpenCv(sequence, slam_options.tracker.preprocess.metric, "opencv_" + size.name());
    c["opencv_ms"] = opencv.ms_per_frame;
    c["opencv_ate_m"] = opencv.ate_m;
    c["opencv_failed_frames"] = opencv.failed_frames;
    c["opencv_threads"] = cv::getNumThreads();
    c["ratio"] = ms_total / opencv.ms_per_frame;
    c["ratio_odometry"] = (preprocess_ms + tracking_ms) / timed / opencv.ms_per_frame;
  }
  if (options().open3d) {
    const Open3dRun open3d = runOpen3d(sequence, slam_options.tracker.preprocess.metric, "open3d_" + size.name());
    c["open3d_ms"] = open3d.ms_per_frame;
    c["open3d_ate_m"] = open3d.ate_m;
    c["open3d_failed_frames"] = open3d.failed_frames;
    c["open3d_threads"] = open3d.threads;
    c["ratio_open3d"] = ms_total / open3d.ms_per_frame;
  }
  state.SetLabel(options().mode + ", " + context().features().device_name);
}

void registerAll() {
  const BenchOptions& o = options();
  for (const Size& size : o.sizes) {
    const std::string suffix = std::string("/") + kPreset + "/" + size.name();
    const std::string slam_name = o.mode == "rgbd" ? "rgbd_slam" : "rgbd_slam_" + o.mode;
    benchmark::RegisterBenchmark((slam_name + suffix).c_str(), rgbdSlam, size)
        ->Iterations(o.frames - 1)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
    if (o.steps) {
      benchmark::RegisterBenchmark(("rgbd_slam_steps" + suffix).c_str(), rgbdSlamSteps, size)
          ->Iterations(o.frames - 1)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
  }
}

}  // namespace
}  // namespace vifusion::bench

namespace {

/// The CPU's "model name" from /proc/cpuinfo (Linux), for the README's speed table; "unknown" elsewhere.
std::string cpuModelName() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  const std::string key = "model name";
  for (std::string line; std::getline(cpuinfo, line);) {
    const std::size_t colon = line.find(':');
    if (line.rfind(key, 0) == 0 && colon != std::string::npos && colon + 2 <= line.size())
      return line.substr(colon + 2);
  }
  return "unknown";
}

}  // namespace

int main(int argc, char** argv) {
  try {
    vifusion::bench::parseOptions(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_rgbd_slam: %s\n", e.what());
    return 2;
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  try {
    benchmark::AddCustomContext("device", vifusion::bench::context().features().device_name);
    benchmark::AddCustomContext("mode", vifusion::bench::options().mode);
    benchmark::AddCustomContext("cpu_model", cpuModelName());
    benchmark::AddCustomContext("sequence", std::string("sim:") + vifusion::bench::kPreset + ", " +
                                                std::to_string(vifusion::bench::options().frames) + " frames" +
                                                (vifusion::bench::options().noise ? "" : ", no noise") +
                                                (vifusion::bench::options().photometric ? "" : ", ICP only"));
    vifusion::bench::registerAll();
    benchmark::RunSpecifiedBenchmarks();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_rgbd_slam: %s\n", e.what());
    return 1;
  }
  benchmark::Shutdown();
  return 0;
}
