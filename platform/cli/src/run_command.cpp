#include "run_command.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "closure_judge.hpp"
#include "frame_budget.hpp"
#include "frame_log.hpp"
#include "progress_bar.hpp"
#include "run_source.hpp"
#include "sim_command.hpp"
#include "vifusion/config/daemon_config.hpp"
#include "vifusion/core/atomic_file.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/core/imu_feed.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/core/version.hpp"
#include "vifusion/datasets/dataset_reader.hpp"
#include "vifusion/eval/metrics.hpp"
#include "vifusion/eval/state_csv.hpp"
#include "vifusion/eval/trajectory_io.hpp"
#include "vifusion/map/surfel_ply.hpp"
#include "vifusion/slam/map_saving.hpp"
#include "vifusion/slam/slam.hpp"
#ifdef VIFUSION_WITH_ZR300
#include "vifusion/zr300/zr300_source.hpp"
#endif

namespace vifusion::cli {
namespace {

double mean(double sum, int count) { return count > 0 ? sum / count : 0.0; }

/// Loop-closure attempts of a run: accepted, refused by test, and the time they took.
class ClosureCounts {
 public:
  void add(const slam::ClosureReport& report) {
    if (report.registration_ms > 0.0) registration_.add(report.registration_ms);
    if (report.deformation_ms > 0.0) deformation_.add(report.deformation_ms);
    if (report.apply_ms > 0.0) apply_.add(report.apply_ms);
    if (report.outcome == slam::ClosureOutcome::kNone) return;
    ms_ = std::max(ms_, report.ms);
    if (report.outcome == slam::ClosureOutcome::kAccepted) {
      ++accepted_;
    } else if (report.outcome == slam::ClosureOutcome::kAgreed) {
      ++agreed_;
    } else {
      ++refused_[static_cast<std::size_t>(report.refusal)];
    }
  }
  int accepted() const { return accepted_; }

  /// {"accepted": N, "agreed": A, "refused": {"residual": M, …}, "max_ms": T, "stages_ms": {"registration": {"count",
  /// "mean", "max"}, "deformation": …, "apply": …}} (ClosureReport's stages; registration counts every frame that
  /// rendered the inactive model, attempts that found nothing in view included)
  nlohmann::json json() const {
    nlohmann::json refused = nlohmann::json::object();
    for (int r = 1; r < slam::kClosureRefusals; ++r) {
      if (refused_[static_cast<std::size_t>(r)] > 0) {
        refused[slam::closureRefusalName(static_cast<slam::ClosureRefusal>(r))] = refused_[static_cast<std::size_t>(r)];
      }
    }
    return {{"accepted", accepted_},
            {"agreed", agreed_},
            {"refused", refused},
            {"max_ms", ms_},
            {"stages_ms",
             {{"registration", registration_.json()}, {"deformation", deformation_.json()}, {"apply", apply_.json()}}}};
  }

 private:
  struct StageTimes {
    int count = 0;
    double sum_ms = 0.0;
    double max_ms = 0.0;
    void add(double ms) {
      ++count;
      sum_ms += ms;
      max_ms = std::max(max_ms, ms);
    }
    nlohmann::json json() const { return {{"count", count}, {"mean", mean(sum_ms, count)}, {"max", max_ms}}; }
  };
  StageTimes registration_, deformation_, apply_;
  int accepted_ = 0;
  int agreed_ = 0;
  std::array<int, slam::kClosureRefusals> refused_{};
  double ms_ = 0.0;
};

/// Frames per tracking state and each state's longest run of consecutive frames.
class TrackingStateCounts {
 public:
  void add(slam::TrackingState state) {
    const auto s = static_cast<std::size_t>(state);
    ++frames_[s];
    run_ = state == last_ ? run_ + 1 : 1;
    last_ = state;
    longest_run_[s] = std::max(longest_run_[s], run_);
  }
  int frames(slam::TrackingState state) const { return frames_[static_cast<std::size_t>(state)]; }

  /// {"tracked": {"frames": N, "longest_run": M}, "imu_carried": …, "lost": …}
  nlohmann::json json() const {
    nlohmann::json states;
    for (const slam::TrackingState state :
         {slam::TrackingState::kTracked, slam::TrackingState::kImuCarried, slam::TrackingState::kLost}) {
      const auto s = static_cast<std::size_t>(state);
      states[slam::trackingStateName(state)] = {{"frames", frames_[s]}, {"longest_run", longest_run_[s]}};
    }
    return states;
  }

 private:
  std::array<int, 3> frames_{};
  std::array<int, 3> longest_run_{};
  slam::TrackingState last_ = slam::TrackingState::kTracked;
  int run_ = 0;
};

/// Recorded frames that could not be read (a truncated PNG, a corrupt message): skipped, counted and each
/// logged once with the reader's reason, which names the file; the report keeps the first kReported.
/// frames.csv's t_ns for a skipped frame whose source lists no time.
constexpr std::int64_t kUnknownFrameTime = -1;

class SkippedFrames {
 public:
  static constexpr std::size_t kReported = 20;

  SkippedFrames() { first_.reserve(kReported); }

  void add(std::size_t frame, const std::string& reason) {
    std::fprintf(stderr, "vifusion run: frame %zu skipped: %s\n", frame, reason.c_str());
    if (first_.size() < kReported) first_.push_back({{"frame", frame}, {"reason", reason}});
    ++count_;
  }
  std::size_t count() const { return count_; }
  nlohmann::json json() const { return {{"count", count_}, {"first", first_}}; }

 private:
  std::size_t count_ = 0;
  std::vector<nlohmann::json> first_;
};

}  // namespace

int runPipeline(const RunOptions& options, std::unique_ptr<zr300::Zr300Backend> backend) {
  slam::SlamOptions slam_options;
  slam_options.mode = slam::slamModeFromName(options.mode);
  slam_options.tracker.use_photometric = options.photometric;
  slam_options.map.capacity = options.map_capacity;
  slam_options.loop.enabled = options.loop_closure;
  slam_options.loop.gravity_term = options.gravity_term;
  slam_options.relocalisation.enabled = options.relocalisation;
  slam_options.mapping = !options.localisation_only;
  if (options.localisation_only && options.load_map.empty()) {
    throw Error("--localisation-only tracks against a saved map: give it with --load-map FILE");
  }
  if (options.localisation_only && !options.save_map.empty()) {
    throw Error("--localisation-only never changes the map: there is nothing new for --save-map to save");
  }
  const bool inertial = slam_options.mode != slam::SlamMode::kRgbd;
  std::filesystem::create_directories(options.out);
  RunSource source;
  SourceRequest request{options.source, options.calibration, options.out, inertial, 0, {}, true};
  request.faults = datasets::parseFaultPlan(options.inject, "--inject");
  if (!openRunSource(request, "vifusion run", std::move(backend), source)) {
    return config::kExitSource;
  }
  const std::unique_ptr<datasets::DatasetReader>& reader = source.reader;
  if (inertial && source.imu == nullptr) {
    throw Error("--mode " + options.mode + " needs IMU data, and " + reader->describe() + " has none");
  }
  if (reader->live()) watchInterrupts(source);

  gpu::GpuOptions gpu_options;
  gpu_options.device = options.device;
  const auto context = gpu::GpuContext::create(gpu_options.withEnvironment());
  slam::Slam pipeline(*context, reader->calibration(), slam_options);
  std::optional<slam::MapLoadReport> loaded;
  if (!options.load_map.empty()) loaded = pipeline.loadMap(options.load_map);

  // A live source has no frame count: it runs until --frames, Ctrl-C or SIGTERM.
  const std::size_t available = reader->live() ? SIZE_MAX : reader->frameCount();
  const std::size_t total = options.max_frames > 0 ? std::min<std::size_t>(options.max_frames, available) : available;
  const std::size_t reserved = std::min(total, kLiveReservedFrames);
  std::vector<eval::StampedPose> trajectory;
  trajectory.reserve(reserved);
  std::vector<eval::StateRecord> states;
  states.reserve(inertial ? reserved : 0);
  FrameLog frame_log(reserved);
  int imu_issues = 0;
  int relocalisations = 0;
  std::size_t relocalising_frames = 0;  ///< a loaded map's first frames, before the camera was located in it
  std::optional<NavState> last_state;   ///< the estimator's, for a saved map
  RgbdFrame frame;
  TrackingStateCounts states_seen;
  ClosureCounts closures;
  ClosureJudge closure_judge(reader->groundTruth());
  FrameBudget budget;
  double iterations = 0.0;
  uint32_t surfels = 0, map_overflow = 0;
  uint64_t map_evicted = 0;
  ProgressBar progress("tracking", static_cast<int64_t>(reserved));
  const auto start = std::chrono::steady_clock::now();
  SkippedFrames skipped;
  std::size_t consumed = 0;                     ///< frames taken from the source, the skipped ones included
  std::optional<std::string> bad_input;         ///< --strict: why the run stopped early
  std::optional<std::string> pipeline_failure;  ///< why the GPU pipeline stopped the run (a lost device)
  const std::optional<std::size_t> device_lost_at = request.faults.deviceLostFrame();
  // IMU rows the reader left out (the estimator sees each hole as a gap): logged once each; --strict stops
  // before the first frame.
  const std::span<const std::string> skipped_imu = reader->skippedImuRows();
  for (const std::string& reason : skipped_imu)
    std::fprintf(stderr, "vifusion run: IMU row skipped: %s\n", reason.c_str());
  if (options.strict && !skipped_imu.empty()) bad_input = skipped_imu.front();
  while (!bad_input && consumed < total && !interrupted()) {
    bool more = false;
    try {
      more = reader->nextFrame(frame);
    } catch (const Error& error) {
      if (reader->live()) throw;  // the live driver recovers by itself; an error from it is final
      if (options.strict) {
        bad_input = "frame " + std::to_string(consumed) + ": " + error.what();
        break;
      }
      frame_log.addUnreadable(reader->listedFrameTimeNs(consumed).value_or(kUnknownFrameTime));
      skipped.add(consumed++, error.what());
      continue;
    }
    if (!more) break;
    ++consumed;
    const std::span<const ImuSample> imu =
        inertial ? source.imu->samplesThrough(frame.t_ns) : std::span<const ImuSample>();
    if (device_lost_at && frame.index >= static_cast<std::int64_t>(*device_lost_at)) context->simulateDeviceLoss();
    slam::FrameResult result;
    try {
      result = pipeline.process(frame, imu);
    } catch (const Error& error) {
      // The GPU is gone (or the pipeline broke): stop here, and still write everything the frames before it gave.
      pipeline_failure = "frame " + std::to_string(frame.index) + ": " + error.what();
      break;
    }
    if (result.closure.outcome == slam::ClosureOutcome::kAccepted) {
      // The map moved: so does the trajectory that built it (frame i is the i-th pose kept).
      for (std::size_t i = 0; i < trajectory.size(); ++i) {
        trajectory[i].T_world_body =
            pipeline.deformPose(trajectory[i].T_world_body, pipeline.firstFrameIndex() + static_cast<std::uint32_t>(i));
      }
    }
    closures.add(result.closure);
    closure_judge.add(result);
    trajectory.push_back({result.t_ns, result.T_W_C});
    frame_log.add(result);
    if (result.inertial) {
      states.push_back({result.t_ns, result.state, result.state_variance});
      last_state = result.state;
    }
    if (result.imu_issue && ++imu_issues <= 10) {  // the report counts them all
      std::fprintf(stderr, "vifusion run: frame %lld: IMU not used: %s\n", static_cast<long long>(frame.index),
                   result.imu_issue->message().c_str());
    }
    states_seen.add(result.tracking);
    relocalisations += result.relocalised ? 1 : 0;
    relocalising_frames += result.relocalising ? 1 : 0;
    budget.add(result);
    surfels = result.surfels;
    map_overflow = result.map_overflow;
    map_evicted += result.map_evicted;
    iterations += result.iterations;
    progress.update(static_cast<int64_t>(trajectory.size()));
  }
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  nlohmann::json camera_report;
  forgetSource();
#ifdef VIFUSION_WITH_ZR300
  if (const auto* camera = dynamic_cast<const zr300::Zr300Source*>(reader.get())) {
    const zr300::Zr300Stats stats = camera->stats();
    camera_report = {{"frames", stats.frames},
                     {"rejected_frames", stats.rejected_frames},
                     {"unpaired_depth", stats.unpaired_depth},
                     {"unpaired_colour", stats.unpaired_colour},
                     {"depth_dropped", stats.depth_dropped},
                     {"colour_dropped", stats.colour_dropped},
                     {"event_timestamps", stats.event_timestamps},
                     {"kernel_timestamps", stats.kernel_timestamps},
                     {"unplugs", stats.unplugs},
                     {"reopens", stats.reopens},
                     {"imu_samples", stats.motion.imu_samples},
                     {"imu_overruns", stats.motion.imu_overruns},
                     {"clock_offset_ns", stats.motion.clock_offset_ns},
                     {"clock_skew_ppm", stats.motion.clock_skew_ppm}};
  }
#endif
  if (reader->live()) {
    std::signal(SIGINT, SIG_DFL);
    std::signal(SIGTERM, SIG_DFL);
  }

  // A loaded map's first frames, before the camera was located in it, have no pose: they are left out.
  const std::vector<eval::StampedPose> located(trajectory.begin() + static_cast<std::ptrdiff_t>(relocalising_frames),
                                               trajectory.end());
  // Every output is written atomically (core/atomic_file.hpp): an interrupted or killed run leaves the
  // previous complete file or the new one, never a truncated file.
  const std::filesystem::path trajectory_path = std::filesystem::path(options.out) / "trajectory.txt";
  eval::writeTum(trajectory_path, located);

  frame_log.write(std::filesystem::path(options.out) / "frames.csv");
  if (inertial) {
    eval::writeEstimatedStates(std::filesystem::path(options.out) / "states.csv", states);
  }

  const int frames = static_cast<int>(trajectory.size());
  nlohmann::json report = {
      {"vifusion_version", versionString()},
      {"source", options.source},
      {"dataset", reader->describe()},
      {"mode", options.mode},
      {"device", context->features().device_name},
      {"frames", frames},
      {"lost_frames", states_seen.frames(slam::TrackingState::kLost)},
      {"tracking_states", states_seen.json()},
      {"loop_closure", options.loop_closure},
      {"localisation_only", options.localisation_only},
      {"closures", closures.json()},
      {"closures_against_ground_truth", closure_judge.json()},
      {"relocalisation",
       {{"enabled", options.relocalisation},
        {"relocalisations", relocalisations},
        {"keyframes", pipeline.keyframes()}}},
      {"skipped_frames", skipped.json()},
      {"skipped_imu_rows",
       {{"count", skipped_imu.size()},
        {"first", std::vector<std::string>(skipped_imu.begin(),
                                           skipped_imu.begin() + static_cast<std::ptrdiff_t>(std::min(
                                                                     skipped_imu.size(), SkippedFrames::kReported)))}}},
      {"frames_with_imu_issues", imu_issues},
      {"ms_per_frame", budget.wallJson()},
      {"gpu_ms_per_frame", budget.gpuJson()},
      {"surfels", surfels},
      {"map_overflow_surfels", map_overflow},
      {"map_evicted_surfels", map_evicted},
      {"gauss_newton_iterations_per_frame", mean(iterations, frames)},
      {"frames_per_s", frames / wall_s},
      {"arena_bytes", pipeline.arenaBytes()}};
  if (!camera_report.is_null()) report["camera"] = camera_report;
  if (bad_input) report["stopped_at_bad_input"] = *bad_input;
  if (loaded) {
    report["loaded_map"] = {{"path", options.load_map},
                            {"bytes", loaded->bytes},
                            {"mode", loaded->mode},
                            {"surfels", loaded->surfels},
                            {"keyframes", loaded->keyframes},
                            {"load_ms", loaded->elapsed_ms},
                            {"relocalising_frames", relocalising_frames},
                            {"located", relocalising_frames < trajectory.size()}};
    if (relocalising_frames < trajectory.size()) {
      report["loaded_map"]["located_after_s"] =
          nsToSeconds(trajectory[relocalising_frames].t_ns - trajectory.front().t_ns);
    }
  }
  if (!reader->groundTruth().empty() && located.size() >= 3) {
    std::vector<eval::StampedPose> ground_truth;
    for (const datasets::StampedPose& pose : reader->groundTruth())
      ground_truth.push_back({pose.t_ns, pose.T_world_body});
    const eval::AteResult ate = eval::ate(ground_truth, located);
    report["ate_rmse_m"] = ate.rmse_m;
  }
  if (!request.faults.empty()) report["injected_faults"] = request.faults.describe();
  if (pipeline_failure) report["stopped_by_pipeline_failure"] = *pipeline_failure;
  try {
    // Stable surfels only (confidence ≥ the map's threshold), as ElasticFusion exports: the
    // unstable ones are mostly single-view noise that tracking never renders.
    std::vector<map::Surfel> map_surfels;
    pipeline.exportMap(map_surfels);
    const std::size_t map_points = map::writeSurfelPly(std::filesystem::path(options.out) / "map.ply", map_surfels,
                                                       map::SurfelPlyOptions::stableOnly(slam_options.map));
    report["map_ply_surfels"] = map_points;
    if (!options.save_map.empty()) {
      std::vector<mapfile::StampedPose> poses;
      poses.reserve(located.size());
      for (const eval::StampedPose& pose : located) poses.push_back({pose.t_ns, pose.T_world_body});
      const slam::MapSaveReport saved =
          slam::saveMap(pipeline, {slam_options.mode, &reader->calibration(), poses, last_state}, options.save_map);
      report["map_file"] = {{"path", options.save_map},
                            {"bytes", saved.bytes},
                            {"surfels", saved.surfels},
                            {"keyframes", saved.keyframes},
                            {"save_ms", saved.elapsed_ms}};
    }
  } catch (const Error& error) {
    if (!pipeline_failure) throw;
    // The map lived on the device that failed: map.ply and the map file keep their previous versions.
    report["map_not_written"] = error.what();
  }

  const std::filesystem::path report_path = std::filesystem::path(options.out) / "report.json";
  writeFileAtomically(report_path, report.dump(2) + "\n");
  std::printf("%s\n", report.dump().c_str());
  if (pipeline_failure) {
    std::fprintf(stderr, "vifusion run: the GPU pipeline failed at %s; the outputs hold the %d frames before it%s\n",
                 pipeline_failure->c_str(), frames,
                 report.contains("map_not_written") ? " (the map could not be read back: not written)" : "");
    return config::kExitGpu;
  }
  if (bad_input) {
    std::fprintf(stderr,
                 "vifusion run: --strict: stopped at the first bad input, %s; the outputs hold the %d frames "
                 "before it\n",
                 bad_input->c_str(), frames);
    return config::kExitSource;
  }
  return 0;
}

int runPipeline(const RunOptions& options) { return runPipeline(options, nullptr); }

}  // namespace vifusion::cli
