#pragma once
// The pipeline per frame (ElasticFusion's): every frame is tracked against the surfel map's prediction at the
// previous pose (frame-to-model), then fused into the map, the map is cleaned and compacted, and the prediction
// for the next frame is rendered — all in one command sequence per map parity, recorded once. After a tracked
// frame, local loop closure (loop_closure.hpp) may deform the map onto its inactive part and move the pose.
// W is the first camera frame (DESIGN §3). Modes (the paper's ablations):
//  - rgbd: the dense tracker alone (DenseTracker::track, constant-velocity guess);
//  - rgbdi, gyro: the two-state estimator (estimator/two_state_estimator.hpp) with the dense terms and the
//    IMU samples between the frames. It starts at the first frame (gravity from the accelerometer window
//    before it); a frame whose IMU samples are refused (gap, disorder, …) is tracked RGB-D only, reported,
//    and the estimator restarts from that pose keeping its velocity, biases and gravity as prior means.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "vifusion/core/rig_calibration.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/core/sensor_data.hpp"
#include "vifusion/core/state.hpp"
#include "vifusion/estimator/two_state_estimator.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/gpu/gpu_context.hpp"
#include "vifusion/gpu/memory_arena.hpp"
#include "vifusion/gpu/timestamp_pool.hpp"
#include "vifusion/map/map_buffers.hpp"
#include "vifusion/map/map_export.hpp"
#include "vifusion/map/map_import.hpp"
#include "vifusion/map/map_maintenance.hpp"
#include "vifusion/map/model_prediction.hpp"
#include "vifusion/map/surfel_fusion.hpp"
#include "vifusion/mapfile/map_sections.hpp"
#include "vifusion/slam/dense_terms_options.hpp"
#include "vifusion/slam/dense_tracker.hpp"
#include "vifusion/slam/loop_closure.hpp"
#include "vifusion/slam/map_loading.hpp"
#include "vifusion/slam/reference_fill.hpp"
#include "vifusion/slam/relocaliser.hpp"
#include "vifusion/slam/tracking_state.hpp"

namespace vifusion::slam {

class TrackerDenseTerms;

enum class SlamMode { kRgbd, kRgbdInertial, kGyro };
/// "rgbd", "rgbdi" or "gyro"; throws vifusion::Error naming the valid values otherwise.
SlamMode slamModeFromName(const std::string& name);
const char* slamModeName(SlamMode mode);

struct SlamOptions {
  SlamMode mode = SlamMode::kRgbd;
  TrackerOptions tracker;
  /// Inertial modes: the estimator's mode and iteration schedule are set from `mode` and `tracker`.
  estimator::EstimatorOptions estimator;
  /// rgbdi mode: how the dense terms enter the estimator (gyro mode takes them unscaled and whole: without
  /// the accelerometer nothing else determines translation).
  DenseTermsOptions dense_terms;
  /// Inertial modes: gap and re-integration rules; the noise is taken from the calibration.
  imu::ImuOptions imu;
  map::MapOptions map;
  map::FusionOptions fusion;
  map::MaintenanceOptions maintenance;
  map::PredictionOptions prediction;  ///< `levels` is taken from the tracker
  /// Inertial modes: when an IMU-carried frame is fused (tracking_state.hpp).
  ImuCarryOptions carry;
  /// rgbd mode: when the photometric term uses the reference view's fill-in (reference_fill.hpp).
  ReferenceFillOptions fill;
  /// Local loop closure by map deformation (loop_closure.hpp); `enabled = false` is open-loop odometry.
  LoopClosureOptions loop;
  /// Relocalisation of a lost camera by place recognition (relocaliser.hpp).
  RelocalisationOptions relocalisation;
  /// false: localisation only, the mode a fleet robot runs in day to day. Frames are tracked against a loaded map
  /// (loadMap before the first frame) and never change it: nothing is fused, no surfel ages or is removed, no loop
  /// closure deforms it, no keyframe is added. Tracking's model is then every stable surfel whatever its age
  /// (map::PredictedSurfels::kStable): with nothing fused no surfel is ever updated, so the active model would
  /// empty within the time window.
  bool mapping = true;

  /// Throws vifusion::Error naming the field out of range.
  void validate() const;
};

/// The map update's stages on the GPU [ms], from device timestamps around them in the frame's map-update
/// submission (gpu/timestamp_pool.hpp); −1 where the device has no timestamps, and fusion and maintenance −1 for
/// a frame that was not fused. Their sum is the submission's GPU time; FrameResult::mapping_ms adds the host's
/// waits, the loop closure and relocalisation.
struct MapStageTimes {
  double fusion_ms = -1.0;       ///< index map, association, fusion, new surfels
  double maintenance_ms = -1.0;  ///< cleanup and compaction
  double prediction_ms = -1.0;   ///< the active model's prediction, every pyramid level
  double reference_ms = -1.0;    ///< the prediction into the tracker's reference view, coverage, fill-in, gradients
};

struct FrameResult {
  int64_t t_ns = 0;
  SE3d T_W_C;                                        ///< camera pose in the map world (first camera frame)
  TrackingState tracking = TrackingState::kTracked;  ///< tracking_state.hpp; the first frame is kTracked
  /// Inertial frames the dense terms did not track: the pose's σ_p at the far end of the depth range, the
  /// quantity ImuCarryOptions bounds [m]; 0 otherwise
  double pose_sigma_m = 0.0;
  double icp_inliers = 0.0;     ///< level-0 ICP inliers of the last iteration
  double icp_candidates = 0.0;  ///< level-0 pixels landing on the model prediction
  double icp_energy = 0.0;      ///< TrackingResult::icp_energy of the frame's tracking
  /// The share of this frame's valid level-0 pixels that the map's prediction at its pose covers, before (in
  /// rgbd mode) the fill-in (reference_fill.hpp) fills the rest; −1 for a frame that was not fused (not counted)
  double coverage = -1.0;
  /// rgbd tracking: the frame was tracked with the previous frame's fill-in (reference_fill.hpp): the map
  /// covered too little of the view, or the frame failed against the map's pixels alone
  bool used_reference_fill = false;
  double rgb_inliers = 0.0;  ///< level-0 photometric inliers of the last iteration
  int iterations = 0;        ///< Gauss-Newton iterations over all levels
  uint32_t surfels = 0;      ///< surfels in the map after this frame
  /// of which in the active range the next frame's passes visit (map_buffers.hpp): what a frame's mapping costs.
  /// All of them after a frame whose loop closure moved the map: the next frame visits the whole map (a closure
  /// that only reactivated surfels moves them into the active range instead: surfel_reactivation.hpp)
  uint32_t active_surfels = 0;
  uint32_t map_overflow = 0;   ///< surfels that did not fit so far (map-full policy: map_maintenance.hpp)
  uint32_t map_evicted = 0;    ///< inactive surfels the map-full policy evicted in this frame
  double preprocess_ms = 0.0;  ///< wall time of upload + preprocessing
  double tracking_ms = 0.0;    ///< wall time of all Gauss-Newton iterations
  double mapping_ms = 0.0;     ///< wall time of fusion, cleanup, compaction, prediction, loop closure, relocalisation
  MapStageTimes map_stages;    ///< the map update's GPU stages
  /// Inertial modes: the estimator holds this frame's state (tracked, or started or restarted at this
  /// frame); false in rgbd mode and while the estimator waits for IMU samples to start from.
  bool inertial = false;
  NavState state;                                ///< the estimator's state (when `inertial`)
  Vector18d state_variance = Vector18d::Zero();  ///< its marginal variances in δx (0: held dims)
  double imu_chi2 = 0.0;                         ///< estimator::FrameSolve::imu_chi2
  double vision_chi2 = 0.0;                      ///< estimator::FrameSolve::vision_chi2
  bool vision_rejected = false;                  ///< estimator::FrameSolve::vision_rejected (then not kTracked)
  std::optional<imu::ImuSampleIssue> imu_issue;  ///< why the IMU could not be used this frame
  /// This frame's loop-closure attempt; kAccepted: T_W_C is already the corrected pose, and the poses of earlier
  /// frames move by Slam::deformPose.
  ClosureReport closure;
  /// map → odom (REP-105): every accepted closure's camera correction T_W'_W so far, composed (identity before
  /// the first). T_W_O⁻¹·T_W_C is the odometry pose T_O_C: the pose as if no closure had moved it, continuous from
  /// frame to frame, while T_W_O jumps at a closure.
  SE3d T_W_O;

  /// The frame was lost to the recovery's own guesses and tracked from a recognised place (relocaliser.hpp):
  /// its pose jumps to where the map says the camera is (the odometry's too: nothing continuous links it to
  /// the last tracked frame).
  bool relocalised = false;

  /// A loaded map's camera not located yet (map_loading.hpp): tracking is kLost, nothing is fused, T_W_C is
  /// not a pose.
  bool relocalising = false;
  /// A `relocalised` frame's agreement with the keyframe it was placed by, image to image
  /// (loop/keyframe_agreement.hpp): a diagnostic of the place verification, not a test of it. Zeros otherwise.
  loop::KeyframeAgreement place_agreement;
  /// A frame of a loaded map's camera that the keyframes did not place, searched for in the whole map
  /// (Slam::searchMap): the distinct places the search proposed, and how many of them the dense verification
  /// passed (more than one distinct: ambiguous, not located). 0 when no search ran.
  int map_search_hypotheses = 0;
  int map_search_verified = 0;
  /// The best hypothesis's cost and inlier share (loop::PlaceHypothesis); 1 and 0 when no search ran.
  double map_search_cost = 1.0;
  double map_search_inliers = 0.0;

  /// Not fused, and the pose is no more than a guess.
  bool lost() const { return tracking == TrackingState::kLost; }
};

class Slam {
 public:
  /// Sizes every GPU buffer (tracker, map, prediction) for the calibration's camera and allocates
  /// the arena once; records every command sequence once.
  Slam(gpu::GpuContext& context, const RigCalibration& calibration, const SlamOptions& options);
  ~Slam();

  /// Tracks and maps one frame. `imu` holds the IMU samples on the IMU clock (t_imu = t_cam +
  /// calibration.time_shift_cam_imu_ns), at least those since the previous frame (a whole recording's
  /// stream is fine: the frame's part is found by binary search); rgbd mode ignores it. No allocation
  /// after the first call.
  FrameResult process(const RgbdFrame& frame, std::span<const ImuSample> imu = {});

  /// Reads the live surfels of the map (in W) into `surfels`, chunk by chunk through a small
  /// staging buffer. For the end of a run or shutdown, not the per-frame path: it allocates.
  void exportMap(std::vector<map::Surfel>& surfels) { exporter_->read(surfels); }

  /// Starts from the map saved in `path` (map_loading.hpp) instead of an empty one; call before the first frame.
  /// @throws vifusion::Error naming the file and the section when it cannot be read, or what does not fit this
  ///         run (camera size, map capacity, no keyframes, relocalisation or loop closure off); the map is then
  ///         empty again
  ///         and the run may go on as a fresh one.
  MapLoadReport loadMap(const std::string& path);
  /// The frame clock's value at this run's first frame: 0, or after loadMap the saved clock's next frame. Frame
  /// i of this run is frame firstFrameIndex() + i for deformPose.
  std::uint32_t firstFrameIndex() const { return first_frame_index_; }
  /// The frame clock's next value: frames of every run that built the map, this one's so far included.
  std::uint32_t frameClock() const { return frame_index_; }
  /// A loaded map's camera is not located yet (FrameResult::relocalising).
  bool relocalising() const { return relocalising_; }

  /// Visits the live surfels chunk by chunk through the export's staging buffer (map_export.hpp), in map order,
  /// and returns their number: how a map is saved without a host copy of it. Not the per-frame path.
  std::uint32_t visitMap(const map::MapExport::ChunkVisitor& visit) { return exporter_->visitChunks(visit); }
  /// The map's counters after the last frame.
  map::MapState mapState() const { return map_->readState(*arena_); }
  /// The relocalisation keyframes; null when relocalisation is off.
  const loop::FernDatabase* keyframeDatabase() const { return relocaliser_ ? &relocaliser_->database() : nullptr; }

  /// After a frame whose closure was accepted, the pose T_W_C of an earlier frame `frame` moved with the map
  /// (its position bound to the deformation graph by time, as the surfels are); unchanged without loop closure.
  SE3d deformPose(const SE3d& T_W_C, std::uint32_t frame) const {
    return loop_closure_ ? loop_closure_->deformPose(T_W_C, frame) : T_W_C;
  }

  /// Keyframes in the relocalisation database (0 when relocalisation is off).
  int keyframes() const { return relocaliser_ ? relocaliser_->keyframes() : 0; }

  uint64_t arenaBytes() const { return arena_->allocatedBytes(); }
  const gpu::MemoryArena& arena() const { return *arena_; }
  const map::MapBuffers& map() const { return *map_; }

 private:
  /// What a frame's map update does after tracking.
  enum class MapUpdate {
    kFuse,            ///< fuse, clean, predict, and take the frame into the reference view (coverage, fill-in)
    kPredictTracked,  ///< localisation only: predict and take the tracked frame into the reference view
    kPredictLost,     ///< a lost frame: predict only (its pose is a guess, its maps stay out of the reference)
  };
  void recordMapUpdate(gpu::CommandRecorder& recorder, int parity, MapUpdate update) const;
  /// The stage times of the map update that just completed (the timestamps recordMapUpdate wrote).
  MapStageTimes readMapStages(bool fused) const;
  /// Frame-to-model tracking by the dense terms alone from the constant-velocity guess, its rotation
  /// pre-aligned; after a lost frame also from the last tracked pose (recovery); with the reference fill-in
  /// where the map covers too little of the view, or as the fallback of a guess that fails against the map's
  /// pixels (reference_fill.hpp). Sets result.T_W_C and updates the constant-velocity guess.
  void trackRgbd(FrameResult& result);
  /// The dense tracker from one guess: with the fill-in when the map covers too little of the reference view,
  /// else against the map's pixels and, when that fails, with the fill-in too.
  TrackingResult trackMapThenFill(const SE3d& T_reference_current_guess);
  /// Whether T_reference_current, estimated for the frame at t_ns, moves the camera faster than
  /// TrackerOptions::max_speed_mps since the reference frame (false while no frame's stamp is the reference).
  bool fasterThanThePlatform(const SE3d& T_reference_current, std::int64_t t_ns) const;
  /// Whether the frame at t_ns comes more than TrackerOptions::max_continued_motion_s after the reference frame.
  bool beyondTheContinuedMotion(std::int64_t t_ns) const;
  /// For a frame the other guesses lost: looks it up among the keyframes and tracks it against the map rendered
  /// at the nearest one's pose (a place guess). True, with `tracking` relative to that pose and T_W_place set,
  /// when that passes the tracker's tests and the relocaliser's inlier test; the reference view is then the
  /// map at the keyframe's pose, else it is left for the caller to render again.
  bool relocalise(TrackingResult& tracking, SE3d& T_W_place);
  /// The two-state estimator's frame; falls back to trackRgbd() when the IMU samples are refused.
  void trackInertial(std::int64_t t_imu_ns, std::span<const ImuSample> imu, FrameResult& result);
  /// kImuCarried while the estimator's pose uncertainty is within ImuCarryOptions' bound, else kLost.
  TrackingState carriedOrLost(FrameResult& result) const;
  /// Starts the estimator at result.T_W_C; `previous` gives velocity, biases and gravity if it ran before.
  /// After a tracked frame's map update: tries a loop closure and on acceptance moves the pose, the reference
  /// view and the estimator with the map.
  void closeLoop(FrameResult& result);
  void startEstimator(std::int64_t t_imu_ns, std::span<const ImuSample> imu, const NavState* previous,
                      FrameResult& result);
  /// For a loaded map's camera in the inertial modes, when the keyframes did not place the frame: the whole map
  /// searched for it (loop/global_place_search.hpp; "up" from the accelerometer over the estimator's gravity
  /// window), each distinct hypothesis tracked against every stable surfel rendered there (a place guess) with
  /// the tests of a frame that ends a loss. True, with `tracking` relative to T_W_place, when exactly one place
  /// passes: a frame two places explain (a room's symmetric corners) waits for a view that tells them apart.
  bool searchMap(std::int64_t t_imu_ns, std::span<const ImuSample> imu, TrackingResult& tracking, SE3d& T_W_place,
                 FrameResult& result);
  /// At loadMap in the inertial modes: the search's distance field from the saved stable surfels, its heights from
  /// the saved trajectory, "up" from the saved gravity direction.
  void prepareMapSearch(std::span<const Eigen::Vector3f> surfaces_W, std::span<const mapfile::StampedPose> trajectory,
                        const NavState& state);
  /// A frame of a run that started from a loaded map and is not located yet: relocalise() against the saved
  /// keyframes, then searchMap(); on success the frame is tracked at the place found and the estimator starts
  /// there.
  void locateInLoadedMap(std::int64_t t_imu_ns, std::span<const ImuSample> imu, FrameResult& result);

  SlamMode mode_;
  ImuCarryOptions carry_;
  ReferenceFillOptions fill_;
  double far_depth_m_ = 0.0;        ///< the depth gate's far end: where the IMU-carry bound is taken [m]
  double far_depth_sigma_m_ = 0.0;  ///< the sensor's axial noise there (the tracker's model) [m]
  std::int64_t time_shift_cam_imu_ns_ = 0;
  SE3d T_S_C_;
  double gravity_mps2_ = 0.0;  ///< the calibration's |g|: E_imu's g_W in the inertial modes
  /// The calibration's static accelerometer bias [m/s², in S]: the estimator's prior mean for b_a, and what the
  /// first gravity direction removes from the mean reading.
  Eigen::Vector3d static_accel_bias_S_ = Eigen::Vector3d::Zero();
  gpu::CapacityPlan plan_;
  std::unique_ptr<DenseTracker> tracker_;
  std::unique_ptr<map::MapBuffers> map_;
  std::unique_ptr<map::SurfelFusion> fusion_;
  std::unique_ptr<map::MapMaintenance> maintenance_;
  std::unique_ptr<map::ModelPrediction> prediction_;
  std::unique_ptr<map::MapExport> exporter_;
  std::unique_ptr<map::MapImport> importer_;
  std::unique_ptr<ReferenceFill> reference_fill_;
  std::unique_ptr<LoopClosure> loop_closure_;                ///< when LoopClosureOptions::enabled
  std::unique_ptr<Relocaliser> relocaliser_;                 ///< when RelocalisationOptions::enabled
  std::unique_ptr<TrackerDenseTerms> dense_terms_;           ///< inertial modes
  std::unique_ptr<estimator::TwoStateEstimator> estimator_;  ///< inertial modes
  std::unique_ptr<gpu::MemoryArena> arena_;
  std::unique_ptr<gpu::TimestampPool> timestamps_;  ///< recordMapUpdate's stage boundaries
  /// per parity: MapUpdate::kFuse, or kPredictTracked with mapping off
  std::array<std::unique_ptr<gpu::CommandSequence>, 2> update_;
  std::array<std::unique_ptr<gpu::CommandSequence>, 2> predict_only_;  ///< per parity: predict (lost frames)
  uint32_t frame_index_ = 0;
  uint32_t first_frame_index_ = 0;           ///< firstFrameIndex()
  bool relocalising_ = false;                ///< a loaded map's camera is not located yet
  bool map_loaded_ = false;                  ///< loadMap succeeded
  loop::KeyframeAgreement place_agreement_;  ///< the last relocalise()'s, when it succeeded
  double place_depth_gate_m_ = 0.0;          ///< the ICP's association gate, for place_agreement_
  bool mapping_ = true;                      ///< SlamOptions::mapping
  std::optional<NavState> loaded_state_;     ///< the loaded map's estimator state: gravity and biases to start from
  /// The estimator's state when refused IMU samples stopped it while RGB-D tracking was lost: velocity, biases and
  /// gravity to restart from once RGB-D tracking holds again.
  std::optional<NavState> restart_state_;
  RelocalisationOptions relocalisation_;  ///< SlamOptions::relocalisation (the map search's settings)
  double min_depth_m_ = 0.0;              ///< the depth gate's near end [m]: the search's camera clearance
  std::unique_ptr<loop::GlobalPlaceSearch> map_search_;  ///< after loadMap in the inertial modes
  std::vector<Eigen::Vector3d> map_search_points_;       ///< a frame's block points, sized at loadMap
  /// The reference view's camera: the previous frame's pose, or during a run of lost RGB-D frames the last
  /// tracked one (the map's view the camera is most likely to come back to).
  SE3d T_W_reference_;
  static constexpr std::int64_t kNoReferenceStamp = INT64_MIN;
  /// The stamp of the frame T_W_reference_ was tracked at [ns]; kNoReferenceStamp before the first frame.
  std::int64_t reference_t_ns_ = kNoReferenceStamp;
  SE3d T_W_O_;                ///< FrameResult::T_W_O
  SE3d T_previous_current_;   ///< last motion between two tracked frames: the constant-velocity guess
  int rgbd_lost_frames_ = 0;  ///< RGB-D tracking: lost frames since the last tracked one
  SE3d T_reference_guess_;    ///< during such a run: the pose guessed by continuing the motion, in the reference
};

}  // namespace vifusion::slam
