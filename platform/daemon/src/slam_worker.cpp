#include "vifusion/daemon/slam_worker.hpp"

#include <thread>

#include "vifusion/config/daemon_config.hpp"
#include "vifusion/core/resident_memory.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/gpu/gpu_context.hpp"
#include "vifusion/map/surfel_ply.hpp"
#include "vifusion/service/log.hpp"

namespace vifusion::daemon {

SlamWorker::SlamWorker(slam::Slam& pipeline, const map::MapOptions& map_options, const SlamWorkerOptions& options,
                       SharedState& state)
    : pipeline_(pipeline), map_options_(map_options), options_(options), state_(state) {
  reserveResident(trajectory_, options.expected_frames, mapfile::StampedPose{});
  if (options.imu != nullptr) reserveResident(states_, options.expected_frames, eval::StateRecord{});
}

void SlamWorker::recordImu(std::span<const ImuSample> imu, std::int64_t t_ns) {
  // Windows overlap (a live feed keeps the estimator's gravity history; a recording's feed is its whole stream):
  // only the samples through the first one after this frame are new to the recording.
  for (const ImuSample& sample : imu) {
    if (sample.t_ns <= recorded_imu_t_ns_) continue;
    options_.recorder->pushImu(sample);
    recorded_imu_t_ns_ = sample.t_ns;
    if (sample.t_ns > t_ns) break;
  }
}

void SlamWorker::run() {
  FrameSlot slot;
  std::int64_t next_map_ns = monotonicNowNs() + options_.map_period_ns;
  next_save_ns_ = monotonicNowNs() + options_.map_save_period_ns;
  located_ = !pipeline_.relocalising();
  state_.relocalising = !located_;
  try {
    while (!state_.stop) {
      if (!state_.frames.tryPop(slot)) {
        if (state_.source_done && state_.frames.size() == 0) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
        continue;
      }
      // Each pop swaps the slot's buffers back into the ring: skipping allocates nothing.
      while (options_.take_newest && state_.frames.tryPop(slot)) ++state_.frames_skipped;
      const std::span<const ImuSample> imu =
          options_.imu != nullptr ? options_.imu->samplesThrough(slot.frame.t_ns) : std::span<const ImuSample>();
      if (options_.recorder != nullptr) recordImu(imu, slot.frame.t_ns);
      if (options_.lose_device_at_frame && options_.gpu != nullptr &&
          slot.frame.index >= static_cast<std::int64_t>(*options_.lose_device_at_frame)) {
        options_.gpu->simulateDeviceLoss();
      }
      const slam::FrameResult result = pipeline_.process(slot.frame, imu);
      if (result.closure.outcome == slam::ClosureOutcome::kAccepted) {
        // The map moved: so does the trajectory that built it (the i-th pose kept is the frame clock's
        // firstFrameIndex() + relocalising frames + i).
        const std::uint32_t first = pipeline_.firstFrameIndex() + relocalising_frames_;
        for (std::size_t i = 0; i < trajectory_.size(); ++i) {
          trajectory_[i].T_W_C = pipeline_.deformPose(trajectory_[i].T_W_C, first + static_cast<std::uint32_t>(i));
        }
        ++state_.closures_accepted;
      } else if (result.closure.outcome == slam::ClosureOutcome::kRefused) {
        ++state_.closures_refused;
      } else if (result.closure.outcome == slam::ClosureOutcome::kAgreed) {
        ++state_.closures_agreed;
      }
      if (result.relocalising) {
        ++relocalising_frames_;
      } else {
        if (!located_) {
          located_ = true;
          state_.relocalising = false;
          service::logLine(service::LogLevel::Info, "located in the loaded map after %u frames: W is its frame",
                           relocalising_frames_);
        }
        if (result.relocalised) ++state_.relocalisations;
        trajectory_.push_back({result.t_ns, result.T_W_C});
        if (result.lost()) ++state_.lost_frames;
      }
      const std::uint64_t processed = state_.frames_processed.load() + 1;
      if (result.tracking == slam::TrackingState::kImuCarried) ++state_.imu_carried_frames;
      if (result.imu_issue) reportImuIssue(slot.frame.index, *result.imu_issue);
      PoseResult output;
      output.t_ns = result.t_ns;
      output.read_ns = slot.read_ns;
      output.sensor_ns = slot.sensor_ns;
      output.done_ns = monotonicNowNs();
      output.T_W_C = result.T_W_C;
      output.T_W_O = result.T_W_O;
      output.tracking = result.tracking;
      output.relocalising = result.relocalising;
      output.inertial = result.inertial;
      output.imu_issue = result.imu_issue.has_value();
      output.surfels = result.surfels;
      output.frame_number = processed;
      if (result.inertial) {
        states_.push_back({result.t_ns, result.state, result.state_variance});
        last_state_ = result.state;
        output.state = result.state;
        output.state_variance = result.state_variance;
      }
      // A full output ring drops this result (counted): the publisher is behind, the pose is stale.
      state_.results.tryPush(output);
      state_.frames_processed = processed;
      // Trade-off: the export reads the map back on this thread (it owns the GPU), costing one
      // readback every map_publish_period_s; converting and publishing happen on the publisher thread.
      if (options_.map_period_ns > 0 && monotonicNowNs() >= next_map_ns) {
        pipeline_.exportMap(snapshot_);
        state_.map.offer(snapshot_, result.t_ns);
        next_map_ns = monotonicNowNs() + options_.map_period_ns;
      }
      offerMapSave(monotonicNowNs());
      if (options_.max_frames > 0 && processed >= options_.max_frames) break;
    }
  } catch (const std::exception& error) {
    service::logLine(service::LogLevel::Error, "pipeline failed: %s", error.what());
    state_.fail(config::kExitGpu);
  }
  writeOutputs();
  state_.slam_done = true;
}

void SlamWorker::offerMapSave(std::int64_t now_ns) {
  MapSaver* saver = options_.map_saver;
  if (saver == nullptr) return;
  const std::uint64_t requested = state_.map_save_requested.load();
  const bool requested_now = requested > answered_request_;
  const bool due = options_.map_save_period_ns > 0 && now_ns >= next_save_ns_;
  if ((!requested_now && !due) || !saver->idle()) return;  // a write in progress: after a later frame
  if (!located_) {
    // Nothing fused yet: the file already is the map. A request is answered (the requester sees no save).
    if (requested_now) {
      service::logLine(service::LogLevel::Info,
                       "map save request %llu: not saved, still relocalising (the file at %s is the map)",
                       static_cast<unsigned long long>(requested), saver->path().c_str());
      state_.map_save_request_done = requested;
    }
  } else {
    captureMap();
    saver->write(requested_now ? requested : 0);
  }
  answered_request_ = requested;
  next_save_ns_ = now_ns + options_.map_save_period_ns;
}

void SlamWorker::captureMap() {
  const slam::MapSaveInputs inputs{options_.mode, options_.calibration, trajectory_, last_state_};
  slam::captureMap(pipeline_, inputs, options_.map_saver->snapshot());
}

bool SlamWorker::saveMapOnStop() {
  MapSaver* saver = options_.map_saver;
  if (!located_) {
    service::logLine(service::LogLevel::Info, "map file %s left as loaded: the camera was never located in it",
                     saver->path().c_str());
    return true;
  }
  saver->waitIdle();
  const std::uint64_t requested = state_.map_save_requested.load();
  try {
    captureMap();
  } catch (const std::exception& error) {
    service::logLine(service::LogLevel::Error, "map not saved on stop (the file at %s is unchanged): %s",
                     saver->path().c_str(), error.what());
    return false;
  }
  saver->write(requested > answered_request_ ? requested : 0);
  answered_request_ = requested;
  return saver->waitIdle();
}

void SlamWorker::reportImuIssue(std::int64_t frame_index, const imu::ImuSampleIssue& issue) {
  const std::uint64_t count = ++state_.imu_issue_frames;
  const std::int64_t now_ns = monotonicNowNs();
  if (now_ns < next_imu_log_ns_) return;  // counted; the message (which allocates) only when logged
  next_imu_log_ns_ = now_ns + kImuIssueLogPeriodNs;
  service::logLine(service::LogLevel::Warning,
                   "frame %lld: IMU not used, tracked RGB-D only: %s (%llu frames without IMU so far; at most "
                   "one such line per %.0f s)",
                   static_cast<long long>(frame_index), issue.message().c_str(), static_cast<unsigned long long>(count),
                   nsToSeconds(kImuIssueLogPeriodNs));
}

void SlamWorker::writeOutputs() {
  try {
    std::filesystem::create_directories(options_.out_dir);
    const std::filesystem::path trajectory_path = options_.out_dir / "trajectory.txt";
    std::vector<eval::StampedPose> poses;
    poses.reserve(trajectory_.size());
    for (const mapfile::StampedPose& pose : trajectory_) poses.push_back({pose.t_ns, pose.T_W_C});
    eval::writeTum(trajectory_path, poses);  // atomically, as every output (core/atomic_file.hpp)
    if (options_.imu != nullptr) eval::writeEstimatedStates(options_.out_dir / "states.csv", states_);
    const std::string states_text =
        options_.imu != nullptr ? ", states.csv (" + std::to_string(states_.size()) + " states)" : "";
    service::logLine(service::LogLevel::Info, "wrote %s (%zu poses)%s", trajectory_path.c_str(), trajectory_.size(),
                     states_text.c_str());
  } catch (const std::exception& error) {
    service::logLine(service::LogLevel::Error, "cannot write the outputs: %s", error.what());
    state_.fail(config::kExitOutput);
  }
  std::vector<map::Surfel> surfels;
  bool exported = false;
  try {
    pipeline_.exportMap(surfels);
    exported = true;
  } catch (const std::exception& error) {  // the device was lost: map.ply keeps its previous version
    service::logLine(service::LogLevel::Error, "map.ply not written: the map cannot be read back: %s", error.what());
    state_.fail(config::kExitGpu);
  }
  if (exported) {
    try {
      const std::size_t written =
          map::writeSurfelPly(options_.out_dir / "map.ply", surfels, map::SurfelPlyOptions::stableOnly(map_options_));
      service::logLine(service::LogLevel::Info, "wrote map.ply (%zu surfels)", written);
    } catch (const std::exception& error) {
      service::logLine(service::LogLevel::Error, "cannot write map.ply: %s", error.what());
      state_.fail(config::kExitOutput);
    }
  }
  if (options_.map_saver != nullptr && !saveMapOnStop()) state_.fail(config::kExitOutput);
}

}  // namespace vifusion::daemon
