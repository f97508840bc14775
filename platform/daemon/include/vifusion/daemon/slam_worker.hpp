#pragma once
// The SLAM thread: the only user of the GPU pipeline. Takes frames from the camera ring, tracks and
// maps them, hands small results to the publisher, and exports the map every map_publish_period_s.
// When it stops (SIGTERM, end of source, max_frames) it finishes the current frame and writes
// trajectory.txt and map.ply atomically (temporary file + rename), and in the inertial modes
// states.csv too (the estimator's state and marginal variances per frame, `vifusion eval --states`).
//
// With a map file (config map_file, map_saver.hpp) it also captures the map for the saver every
// map_save_period_s, when a save was requested (SharedState::map_save_requested) and on stop. A loaded map's
// first frames, before the camera is located in it, are relocalising: they have no pose, are neither kept nor
// counted lost, and nothing is saved until a frame is located (until then the file is the map).
//
// Inertial modes: each frame gets its IMU samples from an ImuFeed (imu_feed.hpp). A frame whose samples
// the pipeline refuses (gap, disorder, not covered, …) is tracked RGB-D only; it is counted in
// SharedState::imu_issue_frames (published in the status message) and logged at most once per
// kImuIssueLogPeriodNs with the count so far — never fatal.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <vector>

#include "vifusion/core/imu_feed.hpp"
#include "vifusion/daemon/map_saver.hpp"
#include "vifusion/daemon/shared_state.hpp"
#include "vifusion/eval/state_csv.hpp"
#include "vifusion/eval/trajectory_io.hpp"
#include "vifusion/mapfile/map_sections.hpp"
#include "vifusion/recording/recorder.hpp"
#include "vifusion/slam/slam.hpp"

namespace vifusion::gpu {
class GpuContext;
}  // namespace vifusion::gpu

namespace vifusion::daemon {

struct SlamWorkerOptions {
  std::filesystem::path out_dir;    ///< trajectory.txt, map.ply (and states.csv) go here
  std::uint64_t max_frames = 0;     ///< 0: until the source ends or stop
  std::int64_t map_period_ns = 0;   ///< map snapshot period [ns]; 0: never
  std::size_t expected_frames = 0;  ///< trajectory capacity reserved up front
  /// Inertial modes: the IMU samples per frame (borrowed; must outlive run()). nullptr: none (rgbd).
  ImuFeed* imu = nullptr;
  /// Records the IMU samples as the frames take them (borrowed; nullptr: not recording).
  recording::Recorder* recorder = nullptr;
  /// realtime: true (a camera, or a replay at its timestamps): when newer frames wait behind the oldest, those are
  /// stale — the newest is processed and the others skipped (SharedState::frames_skipped), so a pipeline slower than
  /// the camera answers within its own processing time instead of working through a queue of old frames (issue 19's
  /// latency: first in first out, a pipeline behind the camera answered four frames late). false (realtime: false, a
  /// replay as fast as possible or a camera whose driver drops instead): every frame, in order.
  bool take_newest = false;
  /// The map file's writer (borrowed; must outlive run()). nullptr: no map file.
  MapSaver* map_saver = nullptr;
  std::int64_t map_save_period_ns = 0;          ///< periodic save [ns]; 0: on stop and on request only
  slam::SlamMode mode = slam::SlamMode::kRgbd;  ///< the pipeline's, for the map file
  const RigCalibration* calibration = nullptr;  ///< the pipeline's rig (borrowed), for the map file
  gpu::GpuContext* gpu = nullptr;               ///< the pipeline's device (borrowed), for fault injection
  /// Config `inject`'s device-lost@K: the device behaves as lost from recorded frame K on (gpu::GpuContext).
  std::optional<std::size_t> lose_device_at_frame;
};

/// Trajectory capacity reserved for a live source, which cannot say how many frames will come: one hour at
/// 30 Hz (64 B a pose, ≈ 310 B a state in inertial modes; reserved address space, resident only once used).
/// A longer run grows the vectors by doubling: one allocation per doubling, not per frame.
inline constexpr std::size_t kLiveTrajectoryReserveFrames = 108'000;

/// At most one log line about refused IMU samples per this period [ns]; the count is always exact.
inline constexpr std::int64_t kImuIssueLogPeriodNs = 5'000'000'000;

class SlamWorker {
 public:
  SlamWorker(slam::Slam& pipeline, const map::MapOptions& map_options, const SlamWorkerOptions& options,
             SharedState& state);
  /// The thread body.
  void run();

 private:
  void writeOutputs();
  /// Counts a refused frame and logs it, rate-limited.
  void reportImuIssue(std::int64_t frame_index, const imu::ImuSampleIssue& issue);

  /// Hands the recorder the samples of `imu` newer than the last one it got, through the first one after the
  /// frame at `t_ns` (later ones come with the next frame).
  void recordImu(std::span<const ImuSample> imu, std::int64_t t_ns);

  /// Captures the map for the saver when a save is due or requested and the saver is idle.
  void offerMapSave(std::int64_t now_ns);
  /// Fills the saver's snapshot from the pipeline (the SLAM thread's share of a save).
  void captureMap();
  /// On stop: the last save, waited for. @returns false when it failed.
  bool saveMapOnStop();

  slam::Slam& pipeline_;
  map::MapOptions map_options_;
  SlamWorkerOptions options_;
  SharedState& state_;
  /// The located frames' poses (a loaded map's relocalising frames have none), in the map file's record.
  std::vector<mapfile::StampedPose> trajectory_;
  std::uint32_t relocalising_frames_ = 0;       ///< frames before the first located one (a loaded map)
  bool located_ = true;                         ///< false until a loaded map's camera is located in it
  std::optional<NavState> last_state_;          ///< the estimator's, for the map file (inertial modes)
  std::uint64_t answered_request_ = 0;          ///< newest map save request taken up
  std::int64_t next_save_ns_ = 0;               ///< host time of the next periodic save [ns]
  std::vector<eval::StateRecord> states_;       ///< inertial modes: the frames the estimator held
  std::int64_t recorded_imu_t_ns_ = INT64_MIN;  ///< newest IMU sample handed to the recorder
  std::vector<map::Surfel> snapshot_;
  std::int64_t next_imu_log_ns_ = 0;  ///< host time from which the next IMU issue may be logged [ns]
};

}  // namespace vifusion::daemon
