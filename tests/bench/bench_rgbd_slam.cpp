// The whole RGB-D pipeline (slam::RgbdSlam: preprocessing, frame-to-model tracking, fusion, map upkeep
// and prediction) on the synthetic living room, at 640×480 and 320×240, beside OpenCV's frame-to-frame
// cv::rgbd::RgbdICPOdometry on the same frames, with the ATE of both against the simulator's ground
// truth, so that speed is never compared at broken accuracy. The goals (not tests): ≥ 15 frames/s
// at 640×480 and ≥ 30 at 320×240 on 2 cores via lavapipe.
//
//   bench_rgbd_slam [--frames=90] [--sizes=640x480,320x240] [--data_dir=DIR] [--vifusion=PATH]
//                   [--noise=1] [--photometric=1] [--opencv=1] [--steps=1] [--trajectory_dir=DIR]
//                   --benchmark_out=slam.json --benchmark_out_format=json
//
// The sequence (`vifusion sim --preset living_room_0`, the first `frames` frames at each size, with
// the simulator's sensor noise unless --noise=0) is generated once into --data_dir and reused; every
// frame is decoded into memory before timing. --photometric=0 tracks with ICP only; --trajectory_dir
// writes both estimates as TUM files.
// Entries, one per size:
//   rgbd_slam/living_room_0/WxH   one iteration per frame after the first (which defines W, starts
//       the map and warms up); real_time = wall time per frame. Counters: ms_preprocess, ms_tracking,
//       ms_mapping, ms_total (mean per timed frame), fps, gn_iterations, ms_per_gn_iteration,
//       lost_frames, surfels (at the end), map_overflow, arena_bytes, ate_m (all frames);
//       opencv_ms, opencv_ate_m, opencv_failed_frames, opencv_threads; ratio = ms_total/opencv_ms,
//       ratio_odometry = (ms_preprocess + ms_tracking)/opencv_ms; goal_fps and goal_met (1/0).
//       cpu_ms_total: process CPU time per frame (lavapipe's threads included), for A/B runs on a
//       shared machine, where wall time follows the other load.
//   rgbd_slam_steps/living_room_0/WxH   the same frames through every kernel of the pipeline, one
//       step per submission (each step's wall time includes a submit and a wait, ≈ 20 µs on
//       lavapipe, so the steps add up to a little more than the fused per-frame sequences), fused at
//       the ground-truth poses: ms_upload, ms_pre_<step>, ms_fusion_<step>, ms_map_cleanup,
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
#include <spawn.h>
#include <time.h>
#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <utility>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/rgbd/depth.hpp>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "vifusion/core/error.hpp"
#include "vifusion/core/image.hpp"
#include "vifusion/datasets/dataset_reader.hpp"
#include "vifusion/eval/metrics.hpp"
#include "vifusion/eval/trajectory_io.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/gpu/gpu_context.hpp"
#include "vifusion/map/map_buffers.hpp"
#include "vifusion/map/map_export.hpp"
#include "vifusion/map/map_maintenance.hpp"
#include "vifusion/map/model_prediction.hpp"
#include "vifusion/map/prediction_cpu.hpp"
#include "vifusion/map/surfel_fusion.hpp"
#include "vifusion/preprocess/preprocess_stage.hpp"
#include "vifusion/slam/rgbd_slam.hpp"
#include "vifusion/tracking/icp_term.hpp"
#include "vifusion/tracking/photometric_term.hpp"
#include "native_loops.hpp"

extern char** environ;

namespace vifusion {
namespace {

constexpr const char* kPreset = "living_room_0";
constexpr double kFrameRateHz = 30.0;  // `vifusion sim` renders at 30 Hz

struct Size {
  int width = 0;
  int height = 0;
  std::string name() const { return std::to_string(width) + "x" + std::to_string(height); }
};

/// Command-line options of this benchmark (Google Benchmark's own --benchmark_* flags come on top).
struct BenchOptions {
  int frames = 90;  ///< frames per sequence, the first one untimed
  std::vector<Size> sizes = {{640, 480}, {320, 240}};
  std::string data_dir = VIFUSION_BENCH_DATA_DIR;  ///< where the generated sequences are kept
  std::string vifusion = VIFUSION_BENCH_CLI;       ///< the `vifusion` program that generates them
  bool noise = true;                               ///< ICL-NUIM-style sensor noise (sim's default); 0: --no-noise
  bool photometric = true;                         ///< TrackerOptions::use_photometric (0: ICP only)
  bool opencv = true;                              ///< run cv::rgbd::RgbdICPOdometry for comparison
  bool steps = true;                               ///< register the per-step entries
  std::string trajectory_dir;                      ///< non-empty: write the estimated trajectories (TUM) here
};

BenchOptions& options() {
  static BenchOptions instance;
  return instance;
}

gpu::GpuContext& context() {
  static const auto instance = gpu::GpuContext::create(gpu::GpuOptions{}.withEnvironment());
  return *instance;
}

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// CPU time of this process (every thread: ours and lavapipe's workers) [ms]. On a shared machine
/// wall time grows with the other load; CPU time much less, so A/B comparisons use both.
double processCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

/// With --trajectory_dir, writes `trajectory` as <dir>/<name>.txt (TUM) for `vifusion eval --plots`.
void writeTrajectory(const std::string& name, const std::vector<eval::StampedPose>& trajectory) {
  if (options().trajectory_dir.empty()) return;
  std::filesystem::create_directories(options().trajectory_dir);
  eval::writeTum(std::filesystem::path(options().trajectory_dir) / (name + ".txt"), trajectory);
}

// ---------------------------------------------------------------------------------------------------
// The sequence: generated once by `vifusion sim`, decoded into memory once per size.

/// One size of the living-room sequence in memory, with the ground truth at every frame.
struct Sequence {
  RigCalibration calibration;
  std::vector<RgbdFrame> frames;
  std::vector<eval::StampedPose> ground_truth;  ///< T_world_camera at each frame's stamp, in frame order
  std::string describe;
};

/// Runs `vifusion sim` with its stdout sent to stderr (stdout may carry the benchmark's JSON).
void runSim(const Size& size, int frames, const std::filesystem::path& out) {
  // `sim` renders floor((duration − first stamp) / period) + 1 frames: half a period of margin.
  char duration[32];
  std::snprintf(duration, sizeof(duration), "%.6f", (frames - 0.5) / kFrameRateHz);
  std::vector<std::string> args = {options().vifusion, "sim", "--preset", kPreset,
                                   "--width", std::to_string(size.width), "--height", std::to_string(size.height),
                                   "--duration", duration, "--out", out.string()};
  if (!options().noise) args.push_back("--no-noise");
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  argv.push_back(nullptr);
  std::fprintf(stderr, "bench_rgbd_slam: generating %d frames of sim:%s at %s into %s\n", frames, kPreset,
               size.name().c_str(), out.c_str());
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, STDERR_FILENO, STDOUT_FILENO);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) throw Error(options().vifusion + ": cannot be started (" + std::strerror(spawned) + "); give --vifusion=PATH");
  int status = 0;
  if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw Error("vifusion sim failed for " + out.string());
  }
}

/// The dataset directory of `size` holding at least `frames` frames, generated if missing or short.
std::filesystem::path datasetFor(const Size& size, int frames) {
  const std::filesystem::path dir = std::filesystem::path(options().data_dir) / (std::string(kPreset) + "_" + size.name() + (options().noise ? "" : "_no_noise"));
  if (std::filesystem::exists(dir / "rgb.txt")) {
    if (datasets::openDataset("dataset:" + dir.string())->frameCount() >= static_cast<std::size_t>(frames)) return dir;
  }
  // Written beside and renamed: an interrupted generation never looks complete.
  const std::filesystem::path partial = dir.string() + ".partial";
  std::filesystem::remove_all(partial);
  std::filesystem::create_directories(partial.parent_path());
  runSim(size, frames, partial);
  std::filesystem::remove_all(dir);
  std::filesystem::rename(partial, dir);
  return dir;
}

const Sequence& sequenceFor(const Size& size) {
  static std::map<std::string, std::unique_ptr<Sequence>> cache;
  auto& slot = cache[size.name()];
  if (slot) return *slot;
  const int frames = options().frames;
  const auto reader = datasets::openDataset("dataset:" + datasetFor(size, frames).string());
  auto sequence = std::make_unique<Sequence>();
  sequence->calibration = reader->calibration();
  sequence->describe = reader->describe();
  sequence->frames.resize(static_cast<std::size_t>(frames));
  for (RgbdFrame& frame : sequence->frames) {
    if (!reader->nextFrame(frame)) throw Error("the dataset ran out of frames: " + reader->describe());
  }
  const std::span<const datasets::StampedPose> truth = reader->groundTruth();
  for (const RgbdFrame& frame : sequence->frames) {
    const auto it = std::lower_bound(truth.begin(), truth.end(), frame.t_ns,
                                     [](const datasets::StampedPose& pose, int64_t t_ns) { return pose.t_ns < t_ns; });
    if (it == truth.end() || it->t_ns != frame.t_ns) throw Error("no ground-truth pose at a frame's stamp: " + reader->describe());
    sequence->ground_truth.push_back({it->t_ns, it->T_world_body});
  }
  slot = std::move(sequence);
  return *slot;
}

// ---------------------------------------------------------------------------------------------------
// OpenCV's RgbdICPOdometry, frame to frame, on the same frames.

struct OpenCvRun {
  double ms_per_frame = 0.0;  ///< mean wall time of compute() over frames 1 … n−1
  double ate_m = std::numeric_limits<double>::quiet_NaN();
  int failed_frames = 0;  ///< compute() returned false: the pose is carried over unchanged
};

SE3d se3FromCv(const cv::Mat& Rt) {
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) R(r, c) = Rt.at<double>(r, c);
    t(r) = Rt.at<double>(r, 3);
  }
  return SE3d(Eigen::Quaterniond(R), t);
}

/// Same intrinsics and depth gate as our preprocessing; every other parameter at OpenCV 4.6's
/// defaults: max depth difference 0.07 m, max points part 0.07, iterations {7, 7, 7, 10} (finest
/// level first, 4 levels), min gradient magnitudes 10 at every level, rigid-body motion, and a
/// failed compute() when the motion exceeds 0.15 m or 15°. Depth is CV_32F metres with NaN where
/// invalid, intensity 8-bit grey (as the opencv_contrib odometry sample); both are converted before
/// timing. OpenCV's own thread pool (cv::getNumThreads()) runs its parallel loops.
OpenCvRun runOpenCv(const Sequence& sequence, const preprocess::DepthToMetricParams& gate, const std::string& name) {
  const PinholeCamera& camera = sequence.calibration.camera;
  const cv::Mat K = (cv::Mat_<float>(3, 3) << static_cast<float>(camera.fx), 0.f, static_cast<float>(camera.cx), 0.f,
                     static_cast<float>(camera.fy), static_cast<float>(camera.cy), 0.f, 0.f, 1.f);
  const cv::Ptr<cv::rgbd::RgbdICPOdometry> odometry =
      cv::rgbd::RgbdICPOdometry::create(K, gate.min_depth_m, gate.max_depth_m);

  std::vector<cv::Mat> depth_m, grey;
  for (const RgbdFrame& frame : sequence.frames) {
    const cv::Mat raw(frame.depth.height(), frame.depth.width(), CV_16UC1, const_cast<uint16_t*>(frame.depth.data()));
    cv::Mat depth;
    raw.convertTo(depth, CV_32FC1, frame.depth_scale_m);
    depth.setTo(std::numeric_limits<float>::quiet_NaN(), raw == 0);
    depth_m.push_back(depth);
    const cv::Mat rgb(frame.rgb.height(), frame.rgb.width(), CV_8UC3, const_cast<Rgb8*>(frame.rgb.data()));
    cv::Mat g;
    cv::cvtColor(rgb, g, cv::COLOR_RGB2GRAY);
    grey.push_back(g);
  }
  const auto frameAt = [&](std::size_t i) {
    return cv::makePtr<cv::rgbd::OdometryFrame>(grey[i], depth_m[i], cv::Mat(), cv::Mat(), static_cast<int>(i));
  };
  {  // warm-up (thread pool, first allocations), not timed
    cv::Ptr<cv::rgbd::OdometryFrame> src = frameAt(1), dst = frameAt(0);
    cv::Mat Rt;
    odometry->compute(src, dst, Rt);
  }

  // compute(current, previous) gives Rt = T_previous_current (p_previous = Rt · p_current); each
  // frame's pyramids are built once, as the source, and completed as the destination next time.
  OpenCvRun run;
  std::vector<eval::StampedPose> trajectory = {{sequence.frames[0].t_ns, SE3d()}};
  cv::Ptr<cv::rgbd::OdometryFrame> previous = frameAt(0);
  double total_ms = 0.0;
  for (std::size_t i = 1; i < sequence.frames.size(); ++i) {
    cv::Ptr<cv::rgbd::OdometryFrame> current = frameAt(i);
    cv::Mat Rt;
    const auto start = std::chrono::steady_clock::now();
    const bool ok = odometry->compute(current, previous, Rt);
    total_ms += msSince(start);
    SE3d T_W_C = trajectory.back().T_world_body;
    if (ok) {
      T_W_C = T_W_C * se3FromCv(Rt);
    } else {
      ++run.failed_frames;
    }
    trajectory.push_back({sequence.frames[i].t_ns, T_W_C});
    previous = current;
  }
  run.ms_per_frame = total_ms / static_cast<double>(sequence.frames.size() - 1);
  run.ate_m = eval::ate(sequence.ground_truth, trajectory).rmse_m;
  writeTrajectory(name, trajectory);
  return run;
}

// ---------------------------------------------------------------------------------------------------
// The pipeline.

double goalFps(const Size& size) { return size.width >= 640 ? 15.0 : 30.0; }

void rgbdSlam(benchmark::State& state, Size size) {
  const Sequence& sequence = sequenceFor(size);
  slam::SlamOptions slam_options;  // defaults, as `vifusion run`
  slam_options.tracker.use_photometric = options().photometric;
  slam::RgbdSlam pipeline(context(), sequence.calibration, slam_options);
  std::vector<eval::StampedPose> trajectory;
  trajectory.reserve(sequence.frames.size());
  // Frame 0 defines W and only starts the map (no tracking): it is the warm-up, not timed.
  trajectory.push_back({sequence.frames[0].t_ns, pipeline.process(sequence.frames[0]).T_W_C});

  double preprocess_ms = 0.0, tracking_ms = 0.0, mapping_ms = 0.0, iterations = 0.0;
  int lost = 0;
  slam::FrameResult last;
  std::size_t next = 1;
  double cpu_ms = 0.0;
  for (auto _ : state) {
    const double cpu_start = processCpuMs();
    last = pipeline.process(sequence.frames[next++]);
    cpu_ms += processCpuMs() - cpu_start;
    trajectory.push_back({last.t_ns, last.T_W_C});
    preprocess_ms += last.preprocess_ms;
    tracking_ms += last.tracking_ms;
    mapping_ms += last.mapping_ms;
    iterations += last.iterations;
    lost += last.lost ? 1 : 0;
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
  writeTrajectory("vifusion_" + size.name(), trajectory);
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
  state.SetLabel(context().features().device_name);
}

/// The kernels of RgbdSlam built on their own, each step in its own command sequence (per
/// surfel-array parity where it matters), in RgbdSlam's order: upload, preprocess steps, tracking
/// (each dense term at each level in its own submission), fusion steps, cleanup, compaction, flip,
/// prediction, the copies of the prediction into the tracker's reference view and the reference's
/// intensity pyramid and gradients. Fusion uses the ground-truth poses (relative to the first
/// frame), so the map grows as in a well-tracked run; tracking runs DenseTracker's Gauss-Newton loop
/// from the constant-velocity guess of those poses, so its iterations per level are realistic.
struct StepPipeline {
  gpu::CapacityPlan plan;
  slam::TrackerOptions tracker_options;
  std::unique_ptr<slam::DenseTracker> tracker;
  std::unique_ptr<map::MapBuffers> map;
  std::unique_ptr<map::SurfelFusion> fusion;
  std::unique_ptr<map::MapMaintenance> maintenance;
  std::unique_ptr<map::ModelPrediction> prediction;
  std::unique_ptr<map::MapExport> exporter;  ///< reads the map for the native prediction
  gpu::BufferId splat_ids_readback;          ///< the GPU's splat winners, to check the native did the same
  std::unique_ptr<gpu::MemoryArena> arena;
  std::unique_ptr<gpu::CommandSequence> splat_ids_copy;
  std::vector<std::unique_ptr<gpu::CommandSequence>> preprocess_steps;
  std::array<std::vector<std::unique_ptr<gpu::CommandSequence>>, 2> fusion_steps;
  std::array<std::unique_ptr<gpu::CommandSequence>, 2> cleanup, compaction, predict;
  std::unique_ptr<gpu::CommandSequence> reference_copy, reference_gradients;

  /// The tracker's terms are private, so each term is built again in a plan of its own (buffer
  /// names are unique per plan) over device-local copies of the tracker's current and reference
  /// maps, refreshed before each frame's tracking (untimed): the same kernels on the same data.
  struct Terms {
    gpu::CapacityPlan plan;
    std::vector<tracking::IcpLevelInputs> icp_inputs;
    std::vector<tracking::PhotometricLevelInputs> photometric_inputs;
    std::vector<std::pair<gpu::BufferId, gpu::BufferId>> copies;  ///< tracker arena → this arena
    std::unique_ptr<tracking::IcpTerm> icp;
    std::unique_ptr<tracking::PhotometricTerm> photometric;
    std::unique_ptr<gpu::MemoryArena> arena;
    std::unique_ptr<gpu::CommandSequence> refresh, level0_readback;
    std::vector<std::unique_ptr<gpu::CommandSequence>> icp_levels, photometric_levels;
    /// Readback copies of the level-0 inputs, which the native loops read.
    gpu::BufferId cur_vertices, cur_normals, cur_intensity, ref_vertices, ref_normals, ref_intensity, ref_gradients;
  } terms;

  StepPipeline(const RigCalibration& calibration, const slam::SlamOptions& options) : tracker_options(options.tracker) {
    gpu::GpuContext& ctx = context();
    const PinholeCamera& camera = calibration.camera;
    tracker = std::make_unique<slam::DenseTracker>(ctx, plan, camera, calibration.depth_scale_m, tracker_options);
    const preprocess::PreprocessStage& stage = tracker->preprocessing();
    const int levels = tracker_options.levels;
    map = std::make_unique<map::MapBuffers>(plan, options.map, camera);
    fusion = std::make_unique<map::SurfelFusion>(ctx, plan, *map, camera, options.fusion);
    maintenance = std::make_unique<map::MapMaintenance>(ctx, plan, *map, camera, options.maintenance);
    map::PredictionOptions prediction_options = options.prediction;
    prediction_options.levels = levels;
    prediction = std::make_unique<map::ModelPrediction>(ctx, plan, *map, camera, prediction_options);
    exporter = std::make_unique<map::MapExport>(ctx, plan, *map);
    splat_ids_readback = plan.addBuffer("bench.splat_ids", plan.buffers()[prediction->splatIds().index].bytes,
                                        gpu::MemoryUse::Readback);

    Terms& t = terms;
    const auto mirror = [&](gpu::BufferId source, gpu::MemoryUse use, const char* suffix) {
      const gpu::BufferRequest& request = plan.buffers()[source.index];
      const gpu::BufferId copy = t.plan.addBuffer(request.name + suffix, request.bytes, use);
      if (use == gpu::MemoryUse::DeviceLocal) t.copies.push_back({source, copy});
      return copy;
    };
    const auto device = gpu::MemoryUse::DeviceLocal;
    for (int l = 0; l < levels; ++l) {
      const preprocess::LevelBuffers& cur = stage.level(l);
      const preprocess::LevelBuffers& ref = tracker->reference(l);
      const gpu::BufferId cur_vertices = mirror(cur.vertices, device, ".bench");
      const gpu::BufferId ref_vertices = mirror(ref.vertices, device, ".bench");
      t.icp_inputs.push_back({cur_vertices, mirror(cur.normals, device, ".bench"), ref_vertices,
                              mirror(ref.normals, device, ".bench")});
      t.photometric_inputs.push_back({cur_vertices, mirror(cur.intensity, device, ".bench"),
                                      mirror(ref.intensity, device, ".bench"), mirror(ref.gradients, device, ".bench"),
                                      ref_vertices});
    }
    const auto readback = gpu::MemoryUse::Readback;
    const preprocess::LevelBuffers& cur0 = stage.level(0);
    const preprocess::LevelBuffers& ref0 = tracker->reference(0);
    t.cur_vertices = mirror(cur0.vertices, readback, ".readback");
    t.cur_normals = mirror(cur0.normals, readback, ".readback");
    t.cur_intensity = mirror(cur0.intensity, readback, ".readback");
    t.ref_vertices = mirror(ref0.vertices, readback, ".readback");
    t.ref_normals = mirror(ref0.normals, readback, ".readback");
    t.ref_intensity = mirror(ref0.intensity, readback, ".readback");
    t.ref_gradients = mirror(ref0.gradients, readback, ".readback");
    t.icp = std::make_unique<tracking::IcpTerm>(ctx, t.plan, levels, tracker_options.icp);
    t.photometric = std::make_unique<tracking::PhotometricTerm>(ctx, t.plan, levels, tracker_options.photometric);

    arena = gpu::MemoryArena::create(ctx, plan);
    tracker->build(*arena);
    fusion->build(*arena, map::FusionInputs::fromPreprocess(stage));
    maintenance->build(*arena);
    prediction->build(*arena);
    exporter->build(*arena);
    map->reset(*arena);
    splat_ids_copy = gpu::CommandSequence::create(ctx, "bench.splat_ids_copy");
    splat_ids_copy->record([&](gpu::CommandRecorder& recorder) {
      recorder.copyBuffer(arena->buffer(prediction->splatIds()), arena->buffer(splat_ids_readback),
                          arena->buffer(splat_ids_readback).bytes);
      recorder.hostReadBarrier();
    });
    t.arena = gpu::MemoryArena::create(ctx, t.plan);
    t.icp->build(*t.arena, t.icp_inputs);
    t.photometric->build(*t.arena, t.photometric_inputs);

    for (const preprocess::PreprocessStep step : preprocess::kAllPreprocessSteps) {
      preprocess_steps.push_back(gpu::CommandSequence::create(ctx, std::string("bench.pre.") + preprocess::preprocessStepName(step)));
      preprocess_steps.back()->record([&](gpu::CommandRecorder& recorder) { stage.recordStep(recorder, step); });
    }
    for (int parity = 0; parity < 2; ++parity) {
      for (const map::FusionStep step : map::kAllFusionSteps) {
        fusion_steps[parity].push_back(gpu::CommandSequence::create(ctx, std::string("bench.fusion.") + map::fusionStepName(step)));
        fusion_steps[parity].back()->record([&](gpu::CommandRecorder& recorder) { fusion->recordStep(recorder, step, parity); });
      }
      cleanup[parity] = gpu::CommandSequence::create(ctx, "bench.cleanup");
      cleanup[parity]->record([&](gpu::CommandRecorder& recorder) {
        maintenance->recordCleanup(recorder, parity);
        recorder.computeBarrier();
      });
      compaction[parity] = gpu::CommandSequence::create(ctx, "bench.compaction");
      compaction[parity]->record([&](gpu::CommandRecorder& recorder) {
        maintenance->recordCompaction(recorder, parity);
        recorder.hostReadBarrier();
      });
      predict[parity] = gpu::CommandSequence::create(ctx, "bench.predict");
      predict[parity]->record([&](gpu::CommandRecorder& recorder) {
        prediction->record(recorder, parity);
        recorder.hostReadBarrier();
      });
    }
    // As RgbdSlam::recordMapUpdate: predicted maps → reference view, then its intensity pyramid and gradients.
    reference_copy = gpu::CommandSequence::create(ctx, "bench.reference_copy");
    reference_copy->record([&](gpu::CommandRecorder& recorder) {
      for (int l = 0; l < levels; ++l) {
        const map::ModelLevelBuffers& model = prediction->level(l);
        const preprocess::LevelBuffers& reference = tracker->reference(l);
        for (auto [from, to] : {std::pair{model.vertices, reference.vertices}, std::pair{model.normals, reference.normals}}) {
          recorder.copyBuffer(arena->buffer(from), arena->buffer(to), arena->buffer(from).bytes);
        }
      }
      const gpu::GpuBuffer& model_intensity = arena->buffer(prediction->level(0).intensity);
      recorder.copyBuffer(model_intensity, arena->buffer(tracker->reference(0).intensity), model_intensity.bytes);
      recorder.hostReadBarrier();
    });
    reference_gradients = gpu::CommandSequence::create(ctx, "bench.reference_gradients");
    reference_gradients->record([&](gpu::CommandRecorder& recorder) {
      tracker->recordReferenceIntensity(recorder);
      recorder.hostReadBarrier();
    });

    for (int l = 0; l < levels; ++l) {
      t.icp_levels.push_back(gpu::CommandSequence::create(ctx, "bench.icp.l" + std::to_string(l)));
      t.icp_levels.back()->record([&](gpu::CommandRecorder& recorder) { t.icp->record(recorder, l); });
      t.photometric_levels.push_back(gpu::CommandSequence::create(ctx, "bench.photometric.l" + std::to_string(l)));
      t.photometric_levels.back()->record([&](gpu::CommandRecorder& recorder) { t.photometric->record(recorder, l); });
    }
    t.refresh = gpu::CommandSequence::create(ctx, "bench.terms_refresh");
    t.refresh->record([&](gpu::CommandRecorder& recorder) {
      for (auto [from, to] : t.copies) recorder.copyBuffer(arena->buffer(from), t.arena->buffer(to), arena->buffer(from).bytes);
      recorder.computeBarrier();
    });
    t.level0_readback = gpu::CommandSequence::create(ctx, "bench.level0_readback");
    t.level0_readback->record([&](gpu::CommandRecorder& recorder) {
      const tracking::IcpLevelInputs& icp0 = t.icp_inputs[0];
      const tracking::PhotometricLevelInputs& photometric0 = t.photometric_inputs[0];
      for (auto [from, to] : {std::pair{icp0.current_vertices, t.cur_vertices}, std::pair{icp0.current_normals, t.cur_normals},
                              std::pair{photometric0.current_intensity, t.cur_intensity},
                              std::pair{icp0.model_vertices, t.ref_vertices}, std::pair{icp0.model_normals, t.ref_normals},
                              std::pair{photometric0.reference_intensity, t.ref_intensity},
                              std::pair{photometric0.reference_gradients, t.ref_gradients}}) {
        recorder.copyBuffer(t.arena->buffer(from), t.arena->buffer(to), t.arena->buffer(from).bytes);
      }
      recorder.hostReadBarrier();
    });
  }

  template <typename T>
  const T* host(gpu::BufferId id) const {
    return terms.arena->buffer(id).hostSpan<const T>().data();
  }
};

/// A wall time and the process CPU time spent meanwhile [ms].
struct Timing {
  double wall_ms = 0.0;
  double cpu_ms = 0.0;
};

/// Accumulates the wall time of each named step ("ms_<step>") and the CPU time the process spent
/// in it, lavapipe's worker threads included ("cpu_ms_<step>"; up to 2× the wall time on 2 cores).
class StepTimes {
 public:
  template <class Fn>
  void time(const std::string& name, Fn&& fn) {
    const double cpu_start = processCpuMs();
    const auto start = std::chrono::steady_clock::now();
    fn();
    totals_[name] += msSince(start);
    totals_["cpu_" + name] += processCpuMs() - cpu_start;
  }
  void add(const std::string& name, double value) { totals_[name] += value; }
  /// `name` and "cpu_<name>" from a Timing.
  void add(const std::string& name, const Timing& timing) {
    totals_[name] += timing.wall_ms;
    totals_["cpu_" + name] += timing.cpu_ms;
  }
  const std::map<std::string, double>& totals() const { return totals_; }

 private:
  std::map<std::string, double> totals_;
};

/// Median wall time and median process CPU time of `repeats` calls of fn [ms].
template <class Fn>
Timing medianMs(int repeats, Fn&& fn) {
  std::vector<double> wall, cpu;
  for (int r = 0; r < repeats; ++r) {
    const double cpu_start = processCpuMs();
    const auto start = std::chrono::steady_clock::now();
    fn();
    wall.push_back(msSince(start));
    cpu.push_back(processCpuMs() - cpu_start);
  }
  const auto median = [](std::vector<double>& v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  return {median(wall), median(cpu)};
}

/// DenseTracker::track's Gauss-Newton loop with each term's submission timed on its own
/// (ms_track_<term>_l<level>, summed over the frame's iterations; gn_iterations_l<level>).
/// Returns T_ref_cur.
SE3d trackTimed(StepPipeline& p, const SE3d& guess, StepTimes& t) {
  const slam::TrackerOptions& o = p.tracker_options;
  SE3d T_ref_cur = guess;
  for (int l = o.levels - 1; l >= 0; --l) {
    const std::string level = "_l" + std::to_string(l);
    const PinholeCamera& camera = p.tracker->camera(l);
    for (int i = 0; i < o.iterations[l]; ++i) {
      p.terms.icp->setPose(l, T_ref_cur, camera);
      t.time("ms_track_icp" + level, [&] { p.terms.icp_levels[l]->run(); });
      NormalEquations6 system = p.terms.icp->result(l);
      if (o.use_photometric) {
        p.terms.photometric->setPose(l, T_ref_cur, camera);
        t.time("ms_track_photometric" + level, [&] { p.terms.photometric_levels[l]->run(); });
        system += p.terms.photometric->result(l);
      }
      t.add("gn_iterations" + level, 1.0);
      const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(system.H);
      if (ldlt.info() != Eigen::Success || system.inliers < 6.0) return T_ref_cur;
      const Vector6d delta = ldlt.solve(-system.b);
      if (!delta.allFinite()) return T_ref_cur;
      T_ref_cur = SE3d::exp(delta) * T_ref_cur;
      if (delta.head<3>().norm() < o.converged_step && delta.tail<3>().norm() < o.converged_step) break;
    }
  }
  return T_ref_cur;
}

/// One level-0 evaluation of each dense term at T_ref_cur on the GPU and as native loops on 1 and 2
/// threads over read-back copies of the same buffers (medians of 3), and the natives' inlier count
/// relative to the GPU's (1 = the same work).
void compareNative(StepPipeline& p, const SE3d& T_ref_cur, StepTimes& t) {
  const PinholeCamera& camera = p.tracker->camera(0);
  const int pixels = camera.width * camera.height;
  p.terms.level0_readback->run();
  using preprocess::GradientPixel;
  using preprocess::NormalPixel;
  using preprocess::VertexPixel;

  p.terms.icp->setPose(0, T_ref_cur, camera);
  t.add("gpu_icp_l0_ms", medianMs(3, [&] { p.terms.icp_levels[0]->run(); }));
  const NormalEquations6 gpu_icp = p.terms.icp->result(0);
  const tracking::IcpParams icp_params = tracking::IcpParams::make(T_ref_cur, camera, p.tracker_options.icp);
  const auto icp_loop = [&](int begin, int end, bench::NativeSums& sums) {
    bench::icpNative(p.host<VertexPixel>(p.terms.cur_vertices), p.host<NormalPixel>(p.terms.cur_normals),
                     p.host<VertexPixel>(p.terms.ref_vertices), p.host<NormalPixel>(p.terms.ref_normals), icp_params, begin, end, sums);
  };
  bench::NativeSums native{};
  t.add("native_icp_l0_ms_1t", medianMs(3, [&] { native = bench::runSplit(pixels, 1, icp_loop); }));
  t.add("native_icp_l0_ms_2t", medianMs(3, [&] { native = bench::runSplit(pixels, 2, icp_loop); }));
  t.add("native_icp_l0_inliers_vs_gpu", gpu_icp.inliers > 0.0 ? native[28] / gpu_icp.inliers : 0.0);

  if (!p.tracker_options.use_photometric) return;
  p.terms.photometric->setPose(0, T_ref_cur, camera);
  t.add("gpu_photometric_l0_ms", medianMs(3, [&] { p.terms.photometric_levels[0]->run(); }));
  const NormalEquations6 gpu_photometric = p.terms.photometric->result(0);
  const tracking::PhotometricParams photometric_params =
      tracking::PhotometricParams::make(T_ref_cur, camera, p.tracker_options.photometric);
  const auto photometric_loop = [&](int begin, int end, bench::NativeSums& sums) {
    bench::photometricNative(p.host<VertexPixel>(p.terms.cur_vertices), p.host<float>(p.terms.cur_intensity),
                             p.host<float>(p.terms.ref_intensity), p.host<GradientPixel>(p.terms.ref_gradients),
                             p.host<VertexPixel>(p.terms.ref_vertices), photometric_params, begin, end, sums);
  };
  t.add("native_photometric_l0_ms_1t", medianMs(3, [&] { native = bench::runSplit(pixels, 1, photometric_loop); }));
  t.add("native_photometric_l0_ms_2t", medianMs(3, [&] { native = bench::runSplit(pixels, 2, photometric_loop); }));
  t.add("native_photometric_l0_inliers_vs_gpu", gpu_photometric.inliers > 0.0 ? native[28] / gpu_photometric.inliers : 0.0);
}

/// The model prediction (the third kernel by time) against a native loop: the CPU references
/// splatModelCpu + resolveModelCpu + subsampleModelCpu, plain float loops over the same surfels
/// (read back first, untimed) doing the same splat, resolve and subsampling on one thread.
/// gpu_prediction_ms re-runs the just-recorded prediction (idempotent); native_prediction_ids_vs_gpu
/// is the fraction of pixels whose winning surfel agrees (1 = the same work).
struct NativePrediction {
  std::vector<map::Surfel> surfels;
  std::vector<Image<std::uint32_t>> scratch;  ///< depth bits, ids
  std::vector<Image<Eigen::Vector4f>> vertices, normals;
  std::vector<Image<float>> intensity;
};

void comparePrediction(StepPipeline& p, int parity, const SE3d& T_C_W, std::uint32_t frame, NativePrediction& n,
                       StepTimes& t) {
  t.add("gpu_prediction_ms", medianMs(3, [&] { p.predict[parity]->run(); }));
  p.splat_ids_copy->run();
  p.exporter->read(n.surfels);
  const map::PredictionParams params = p.prediction->makeParams(T_C_W, frame);
  if (n.scratch.empty()) {
    for (int k = 0; k < 2; ++k) n.scratch.emplace_back(params.view.width, params.view.height, 0u);
    for (int l = 0; l < p.prediction->levels(); ++l) {
      const PinholeCamera& camera = p.prediction->camera(l);
      n.vertices.emplace_back(camera.width, camera.height, Eigen::Vector4f::Zero());
      n.normals.emplace_back(camera.width, camera.height, Eigen::Vector4f::Zero());
      n.intensity.emplace_back(camera.width, camera.height, 0.0f);
    }
  }
  t.add("native_prediction_ms_1t", medianMs(3, [&] {
          map::splatModelCpu(n.surfels, params, n.scratch[0].view(), n.scratch[1].view());
          map::resolveModelCpu(n.surfels, params, std::as_const(n.scratch[1]).view(), n.vertices[0].view(),
                               n.normals[0].view(), n.intensity[0].view());
          for (int l = 1; l < p.prediction->levels(); ++l) {
            map::subsampleModelCpu(std::as_const(n.vertices[0]).view(), std::as_const(n.normals[0]).view(),
                                   std::as_const(n.intensity[0]).view(), l, n.vertices[l].view(), n.normals[l].view(),
                                   n.intensity[l].view());
          }
        }));
  const std::span<const std::uint32_t> gpu_ids = p.arena->buffer(p.splat_ids_readback).hostSpan<const std::uint32_t>();
  const std::uint32_t* cpu_ids = n.scratch[1].data();
  std::size_t same = 0;
  for (std::size_t i = 0; i < gpu_ids.size(); ++i) same += gpu_ids[i] == cpu_ids[i] ? 1 : 0;
  t.add("native_prediction_ids_vs_gpu", double(same) / double(gpu_ids.size()));
  t.add("native_prediction_frames", 1.0);
}

void rgbdSlamSteps(benchmark::State& state, Size size) {
  const Sequence& sequence = sequenceFor(size);
  slam::SlamOptions slam_options;
  slam_options.tracker.use_photometric = options().photometric;
  StepPipeline p(sequence.calibration, slam_options);
  const preprocess::PreprocessStage& stage = p.tracker->preprocessing();
  const SE3d T_C0_world = sequence.ground_truth.front().T_world_body.inverse();
  const auto T_W_C_at = [&](std::size_t i) { return T_C0_world * sequence.ground_truth[i].T_world_body; };
  StepTimes times;
  NativePrediction native_prediction;
  std::size_t next = 0;
  const auto frame = [&](bool timed) {
    const RgbdFrame& rgbd = sequence.frames[next];
    const SE3d T_W_C = T_W_C_at(next);
    const SE3d T_C_W = T_W_C.inverse();
    const auto frame_index = static_cast<std::uint32_t>(next);
    StepTimes warm_up;
    StepTimes& t = timed ? times : warm_up;
    t.time("ms_upload", [&] { stage.upload(rgbd.depth.view(), rgbd.rgb.view()); });
    for (std::size_t s = 0; s < p.preprocess_steps.size(); ++s) {
      t.time(std::string("ms_pre_") + preprocess::preprocessStepName(preprocess::kAllPreprocessSteps[s]),
             [&] { p.preprocess_steps[s]->run(); });
    }
    if (next > 0) {  // the reference view is the prediction at the previous frame's pose
      const SE3d guess = next > 1 ? T_W_C_at(next - 2).inverse() * T_W_C_at(next - 1) : SE3d();
      p.terms.refresh->run();
      const SE3d T_ref_cur = trackTimed(p, guess, t);
      if (timed) compareNative(p, T_ref_cur, t);
    }
    ++next;
    const int parity = p.map->current();
    p.fusion->setFrame(T_W_C, frame_index);
    p.maintenance->setView(T_C_W, frame_index);
    p.prediction->setView(T_C_W, frame_index);
    for (std::size_t s = 0; s < p.fusion_steps[parity].size(); ++s) {
      t.time(std::string("ms_fusion_") + map::fusionStepName(map::kAllFusionSteps[s]), [&] { p.fusion_steps[parity][s]->run(); });
    }
    t.time("ms_map_cleanup", [&] { p.cleanup[parity]->run(); });
    t.time("ms_map_compaction", [&] { p.compaction[parity]->run(); });
    p.map->flip();
    t.time("ms_map_prediction", [&] { p.predict[parity ^ 1]->run(); });
    // Every 10th frame (the map read-back is slow), and always in short runs.
    if (timed && (frame_index % 10 == 9 || options().frames < 20)) {
      comparePrediction(p, parity ^ 1, T_C_W, frame_index, native_prediction, t);
    }
    t.time("ms_reference_copy", [&] { p.reference_copy->run(); });
    t.time("ms_reference_gradients", [&] { p.reference_gradients->run(); });
  };
  frame(false);  // as in rgbd_slam: frame 0 is the warm-up
  for (auto _ : state) frame(true);
  const double timed = static_cast<double>(next - 1);
  for (const auto& [name, total] : times.totals()) state.counters[name] = total / timed;
  // Per-evaluation costs of the terms and their ratios to the native loops (same pose, same buffers).
  auto& c = state.counters;
  for (const char* term : {"icp", "photometric"}) {
    const std::string gpu = std::string("gpu_") + term + "_l0_ms";
    if (c.find(gpu) == c.end()) continue;
    for (const char* threads : {"1t", "2t"}) {
      const std::string native = std::string("native_") + term + "_l0_ms_" + threads;
      c[std::string("ratio_") + term + "_l0_" + threads] = double(c[gpu]) / double(c[native]);
    }
    // The same work in CPU time: robust to other load on a shared machine (wall time is not).
    c[std::string("ratio_cpu_") + term + "_l0"] =
        double(c["cpu_" + gpu]) / double(c[std::string("cpu_native_") + term + "_l0_ms_1t"]);
  }
  // The prediction comparison ran on some frames only: per comparison, not per frame (the loop
  // above divided by the frames; native_prediction_frames is now the share of frames compared).
  if (const double compared = c["native_prediction_frames"]; compared > 0.0) {
    for (const char* name : {"gpu_prediction_ms", "cpu_gpu_prediction_ms", "native_prediction_ms_1t",
                             "cpu_native_prediction_ms_1t", "native_prediction_ids_vs_gpu"}) {
      c[name] = double(c[name]) / compared;
    }
    c["ratio_prediction_1t"] = double(c["gpu_prediction_ms"]) / double(c["native_prediction_ms_1t"]);
    c["ratio_cpu_prediction"] = double(c["cpu_gpu_prediction_ms"]) / double(c["cpu_native_prediction_ms_1t"]);
  }
  c.erase("native_prediction_frames");
  c["surfels"] = p.map->readState(*p.arena).surfel_count;
  state.SetLabel(context().features().device_name);
}

// ---------------------------------------------------------------------------------------------------
// Command line.

bool parseFlag(const char* arg, const char* name, std::string& value) {
  const std::size_t n = std::strlen(name);
  if (std::strncmp(arg, name, n) != 0 || arg[n] != '=') return false;
  value = arg + n + 1;
  return true;
}

std::vector<Size> parseSizes(const std::string& text) {
  std::vector<Size> sizes;
  std::size_t begin = 0;
  while (begin <= text.size()) {
    const std::size_t end = std::min(text.find(',', begin), text.size());
    const std::string item = text.substr(begin, end - begin);
    Size size;
    char x = 0;
    char rest = 0;
    if (std::sscanf(item.c_str(), "%d%c%d%c", &size.width, &x, &size.height, &rest) != 3 || x != 'x' ||
        size.width < 16 || size.height < 16 || size.width % 2 != 0) {
      throw Error("--sizes: '" + item + "' is not WIDTHxHEIGHT (even width, both ≥ 16)");
    }
    sizes.push_back(size);
    begin = end + 1;
  }
  return sizes;
}

bool parseBool(const std::string& flag, const std::string& value) {
  if (value == "1" || value == "true") return true;
  if (value == "0" || value == "false") return false;
  throw Error(flag + ": expected 1 or 0, got '" + value + "'");
}

/// Takes this benchmark's flags out of argv (Google Benchmark rejects flags it does not know).
void parseOptions(int& argc, char** argv) {
  BenchOptions& o = options();
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    std::string value;
    if (parseFlag(argv[i], "--frames", value)) {
      char* end = nullptr;
      const long frames = std::strtol(value.c_str(), &end, 10);
      if (*end != '\0' || frames < 4 || frames > 100000) throw Error("--frames: expected 4 … 100000, got '" + value + "'");
      o.frames = static_cast<int>(frames);
    } else if (parseFlag(argv[i], "--sizes", value)) {
      o.sizes = parseSizes(value);
    } else if (parseFlag(argv[i], "--data_dir", value)) {
      o.data_dir = value;
    } else if (parseFlag(argv[i], "--vifusion", value)) {
      o.vifusion = value;
    } else if (parseFlag(argv[i], "--noise", value)) {
      o.noise = parseBool("--noise", value);
    } else if (parseFlag(argv[i], "--photometric", value)) {
      o.photometric = parseBool("--photometric", value);
    } else if (parseFlag(argv[i], "--opencv", value)) {
      o.opencv = parseBool("--opencv", value);
    } else if (parseFlag(argv[i], "--trajectory_dir", value)) {
      o.trajectory_dir = value;
    } else if (parseFlag(argv[i], "--steps", value)) {
      o.steps = parseBool("--steps", value);
    } else {
      if (std::strcmp(argv[i], "--help") == 0) {
        std::printf(
            "bench_rgbd_slam [--frames=%d] [--sizes=640x480,320x240] [--data_dir=%s]\n"
            "                [--vifusion=%s] [--noise=1] [--photometric=1] [--opencv=1]\n"
            "                [--steps=1] [--trajectory_dir=DIR]\n"
            "                [Google Benchmark flags]\n\n",
            o.frames, o.data_dir.c_str(), o.vifusion.c_str());
      }
      argv[kept++] = argv[i];
    }
  }
  argc = kept;
}

void registerAll() {
  const BenchOptions& o = options();
  for (const Size& size : o.sizes) {
    const std::string suffix = std::string("/") + kPreset + "/" + size.name();
    benchmark::RegisterBenchmark(("rgbd_slam" + suffix).c_str(), rgbdSlam, size)
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
}  // namespace vifusion

int main(int argc, char** argv) {
  try {
    vifusion::parseOptions(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_rgbd_slam: %s\n", e.what());
    return 2;
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  try {
    benchmark::AddCustomContext("device", vifusion::context().features().device_name);
    benchmark::AddCustomContext("sequence", std::string("sim:") + vifusion::kPreset + ", " +
                                                std::to_string(vifusion::options().frames) + " frames" +
                                                (vifusion::options().noise ? "" : ", no noise") +
                                                (vifusion::options().photometric ? "" : ", ICP only"));
    vifusion::registerAll();
    benchmark::RunSpecifiedBenchmarks();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_rgbd_slam: %s\n", e.what());
    return 1;
  }
  benchmark::Shutdown();
  return 0;
}
