#include "vifusion/slam/slam.hpp"

#include <chrono>
#include <string>

#include "tracker_dense_terms.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/estimator/gravity_initialisation.hpp"
#include "vifusion/imu/sample_window.hpp"
#include "vifusion/slam/model_reference.hpp"

namespace vifusion::slam {
namespace {

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// Timestamp slots of one map-update sequence (recordMapUpdate): the boundaries of its stages.
constexpr std::uint32_t kSlotStart = 0;
constexpr std::uint32_t kSlotFused = 1;
constexpr std::uint32_t kSlotMaintained = 2;
constexpr std::uint32_t kSlotPredicted = 3;
constexpr std::uint32_t kSlotEnd = 4;
constexpr std::uint32_t kMapStageSlots = 5;

}  // namespace

SlamMode slamModeFromName(const std::string& name) {
  if (name == "rgbd") return SlamMode::kRgbd;
  if (name == "rgbdi") return SlamMode::kRgbdInertial;
  if (name == "gyro") return SlamMode::kGyro;
  throw Error("mode '" + name + "' is not one of: rgbd, rgbdi, gyro");
}

const char* slamModeName(SlamMode mode) {
  switch (mode) {
    case SlamMode::kRgbdInertial:
      return "rgbdi";
    case SlamMode::kGyro:
      return "gyro";
    case SlamMode::kRgbd:
      break;
  }
  return "rgbd";
}

void SlamOptions::validate() const {
  tracker.validate();
  estimator.validate();
  dense_terms.validate();
  imu.validate();
  map.validate();
  fusion.validate();
  maintenance.validate();
  prediction.validate();
  carry.validate();
  fill.validate();
  loop.validate();
  relocalisation.validate();
}

Slam::Slam(gpu::GpuContext& context, const RigCalibration& calibration, const SlamOptions& options)
    : mode_(options.mode),
      carry_(options.carry),
      fill_(options.fill),
      time_shift_cam_imu_ns_(calibration.time_shift_cam_imu_ns),
      T_S_C_(calibration.T_S_C),
      gravity_mps2_(calibration.imu.gravity_mps2),
      static_accel_bias_S_(calibration.imu.static_accel_bias_mps2),
      mapping_(options.mapping),
      relocalisation_(options.relocalisation) {
  options.validate();
  const PinholeCamera& camera = calibration.camera;
  if (calibration.depth_camera && (calibration.depth_camera->camera.width != camera.width ||
                                   calibration.depth_camera->camera.height != camera.height)) {
    // Relocalisation's ferns sample the raw depth and colour images on one grid (loop/fern_image.hpp).
    throw Error("calibration: the depth camera's images (" + std::to_string(calibration.depth_camera->camera.width) +
                "x" + std::to_string(calibration.depth_camera->camera.height) +
                ") must have the colour camera's size (" + std::to_string(camera.width) + "x" +
                std::to_string(camera.height) + ")");
  }
  tracker_ = std::make_unique<DenseTracker>(context, plan_, calibration, options.tracker);
  map_ = std::make_unique<map::MapBuffers>(plan_, options.map, camera);
  // One depth-noise model for tracking and fusion: the ICP's.
  const tracking::IcpOptions& icp = options.tracker.icp;
  map::FusionOptions fusion = options.fusion;
  fusion.depth_noise = {icp.sigma_z_a_m, icp.sigma_z_b_per_m, icp.sigma_z_z0_m};
  far_depth_m_ = options.tracker.preprocess.metric.max_depth_m;
  min_depth_m_ = options.tracker.preprocess.metric.min_depth_m;
  far_depth_sigma_m_ = icp.axialSigmaAt(far_depth_m_);
  place_depth_gate_m_ = icp.max_distance_m;
  fusion_ = std::make_unique<map::SurfelFusion>(context, plan_, *map_, camera, fusion);
  maintenance_ = std::make_unique<map::MapMaintenance>(context, plan_, *map_, camera, options.maintenance);
  map::PredictionOptions prediction = options.prediction;
  prediction.levels = options.tracker.levels;
  if (!mapping_) prediction.surfels = map::PredictedSurfels::kStable;
  prediction_ = std::make_unique<map::ModelPrediction>(context, plan_, *map_, camera, prediction);
  exporter_ = std::make_unique<map::MapExport>(context, plan_, *map_);
  importer_ = std::make_unique<map::MapImport>(context, plan_, *map_);
  reference_fill_ = std::make_unique<ReferenceFill>(context, plan_, *tracker_);
  if (options.loop.enabled) {
    // Registration bounds what the calibration's depth bias leaves (model_registration.hpp); tracking does not.
    tracking::IcpOptions registration_icp = icp;
    if (calibration.noise) {
      registration_icp.inverse_depth_bias_sigma_per_m =
          static_cast<float>(calibration.noise->depth.inverse_depth_bias_sigma_per_m);
    }
    loop_closure_ = std::make_unique<LoopClosure>(context, plan_, *map_, *prediction_, prediction, fusion,
                                                  registration_icp, far_depth_m_, options.loop);
  }
  if (options.relocalisation.enabled) {
    relocaliser_ = std::make_unique<Relocaliser>(options.relocalisation, camera.width, camera.height);
  }
  if (mode_ != SlamMode::kRgbd) {
    estimator::EstimatorOptions estimator_options = options.estimator;
    estimator_options.mode =
        mode_ == SlamMode::kGyro ? estimator::InertialMode::kGyro : estimator::InertialMode::kRgbdInertial;
    estimator_options.iterations = options.tracker.iterations;
    estimator_options.converged_step_chi2 = options.tracker.converged_step_chi2;
    imu::ImuOptions imu_options = options.imu;
    imu_options.noise = calibration.imu;
    estimator_ = std::make_unique<estimator::TwoStateEstimator>(estimator_options, imu_options, calibration.T_S_C);
    // Only the accelerometer can carry what the dense terms give up: gyro mode takes them whole.
    const DenseTermsOptions dense_terms =
        options.mode == SlamMode::kRgbdInertial
            ? options.dense_terms
            : DenseTermsOptions{.information_scale = 1.0, .icp_min_constraint_share = 0.0};
    dense_terms_ = std::make_unique<TrackerDenseTerms>(*tracker_, dense_terms);
  }

  arena_ = gpu::MemoryArena::create(context, plan_);
  tracker_->build(*arena_);
  fusion_->build(*arena_, map::FusionInputs::fromPreprocess(tracker_->preprocessing()));
  maintenance_->build(*arena_);
  prediction_->build(*arena_);
  exporter_->build(*arena_);
  importer_->build(*arena_);
  reference_fill_->build(*arena_);
  map_->reset(*arena_);
  if (loop_closure_) loop_closure_->build(*arena_);
  timestamps_ = std::make_unique<gpu::TimestampPool>(context, 2 * kMapStageSlots);
  for (int parity = 0; parity < 2; ++parity) {
    update_[parity] = gpu::CommandSequence::create(context, "slam.update" + std::to_string(parity));
    const MapUpdate update = mapping_ ? MapUpdate::kFuse : MapUpdate::kPredictTracked;
    update_[parity]->record([&](gpu::CommandRecorder& recorder) { recordMapUpdate(recorder, parity, update); });
    predict_only_[parity] = gpu::CommandSequence::create(context, "slam.predict" + std::to_string(parity));
    predict_only_[parity]->record(
        [&](gpu::CommandRecorder& recorder) { recordMapUpdate(recorder, parity, MapUpdate::kPredictLost); });
  }
}

Slam::~Slam() = default;

// Fusion reads surfel array `parity` and the compaction writes the survivors to the other one, which
// the prediction renders. The predicted maps are then copied into the tracker's reference view, and a fused
// frame fills its holes for the photometric term.
// Timestamps mark the stage boundaries (kSlot*): the fused sequence writes slots [0, kMapStageSlots), the
// predict-only one the next kMapStageSlots, every slot in both so that one read gets them all.
void Slam::recordMapUpdate(gpu::CommandRecorder& recorder, int parity, MapUpdate update) const {
  const bool fuse = update == MapUpdate::kFuse;
  const bool tracked = update != MapUpdate::kPredictLost;
  // update_ and predict_only_ each write their own slots (readMapStages).
  const std::uint32_t base = tracked ? 0 : kMapStageSlots;
  timestamps_->recordReset(recorder, base, kMapStageSlots);
  timestamps_->recordWrite(recorder, base + kSlotStart);
  int predicted_parity = parity;
  if (fuse) {
    fusion_->record(recorder, parity);
    recorder.computeBarrier();
    timestamps_->recordWrite(recorder, base + kSlotFused);
    maintenance_->record(recorder, parity);
    recorder.computeBarrier();
    timestamps_->recordWrite(recorder, base + kSlotMaintained);
    predicted_parity = parity ^ 1;
  } else {
    timestamps_->recordWrite(recorder, base + kSlotFused);
    timestamps_->recordWrite(recorder, base + kSlotMaintained);
  }
  prediction_->record(recorder, predicted_parity);
  timestamps_->recordWrite(recorder, base + kSlotPredicted);
  recordPredictionAsReference(recorder, *arena_, *prediction_, *tracker_);
  recorder.computeBarrier();
  if (tracked) {  // a lost frame's pose is a guess: its maps stay out of the reference too
    reference_fill_->recordCoverage(recorder);
    recorder.computeBarrier();
    if (mode_ == SlamMode::kRgbd) {  // the inertial modes' dense terms take the reference as fixed (reference_fill.hpp)
      reference_fill_->recordFill(recorder);
      recorder.computeBarrier();
    }
  }
  tracker_->recordReferenceIntensity(recorder);
  timestamps_->recordWrite(recorder, base + kSlotEnd);
  recorder.hostReadBarrier();
}

MapStageTimes Slam::readMapStages(bool fused) const {
  MapStageTimes times;
  std::array<std::uint64_t, kMapStageSlots> ticks{};
  if (!timestamps_->read(fused ? 0 : kMapStageSlots, ticks)) return times;
  if (fused) {
    times.fusion_ms = timestamps_->msBetween(ticks[kSlotStart], ticks[kSlotFused]);
    times.maintenance_ms = timestamps_->msBetween(ticks[kSlotFused], ticks[kSlotMaintained]);
  }
  times.prediction_ms = timestamps_->msBetween(ticks[kSlotMaintained], ticks[kSlotPredicted]);
  times.reference_ms = timestamps_->msBetween(ticks[kSlotPredicted], ticks[kSlotEnd]);
  return times;
}

namespace {

/// The recovery's choice between two guesses: a verified one over a lost one, else the one with more ICP
/// inliers (both lost: the second, the continued motion, is the better guess of where the camera is).
TrackingResult better(const TrackingResult& a, const TrackingResult& b) {
  if (a.lost != b.lost) return a.lost ? b : a;
  if (a.lost) return b;
  return a.icp_inliers > b.icp_inliers ? a : b;
}

}  // namespace

bool Slam::fasterThanThePlatform(const SE3d& T_reference_current, std::int64_t t_ns) const {
  if (reference_t_ns_ == kNoReferenceStamp || t_ns <= reference_t_ns_) return false;
  return T_reference_current.translation().norm() >
         tracker_->options().max_speed_mps * nsToSeconds(t_ns - reference_t_ns_);
}

bool Slam::beyondTheContinuedMotion(std::int64_t t_ns) const {
  return reference_t_ns_ != kNoReferenceStamp &&
         nsToSeconds(t_ns - reference_t_ns_) > tracker_->options().max_continued_motion_s;
}

TrackingResult Slam::trackMapThenFill(const SE3d& T_reference_current_guess) {
  if (reference_fill_->coverage().fills(fill_.max_coverage)) {
    return tracker_->track(T_reference_current_guess, ReferencePixels::kMapAndFill);
  }
  const TrackingResult on_map = tracker_->track(T_reference_current_guess, ReferencePixels::kMap);
  if (!on_map.lost) return on_map;
  return tracker_->track(T_reference_current_guess, ReferencePixels::kMapAndFill);
}

void Slam::trackRgbd(FrameResult& result) {
  // A loss longer than the recovery window: the lost frames hold the last guess.
  if (rgbd_lost_frames_ > 0 && beyondTheContinuedMotion(result.t_ns)) T_previous_current_ = SE3d();
  // The motion since the previous frame as it was, its rotation pre-aligned to the previous frame's images.
  const SE3d motion = tracker_->prealignRotation(T_previous_current_);
  TrackingResult tracking;
  if (rgbd_lost_frames_ == 0) {
    tracking = trackMapThenFill(motion);
    T_reference_guess_ = motion;
  } else {
    // The reference is still the last tracked view: the camera is back at (or never left) that pose, or it
    // kept moving as it did; whichever guess tracks, verified, wins.
    T_reference_guess_ = T_reference_guess_ * motion;
    tracking = better(trackMapThenFill(SE3d()), trackMapThenFill(T_reference_guess_));
    if (!tracking.lost && relocaliser_ && !relocaliser_->looksLikeLastTracked()) tracking.lost = true;
    SE3d T_W_place;
    if (tracking.lost && relocalise(tracking, T_W_place)) {
      T_W_reference_ = T_W_place;
      T_previous_current_ = SE3d();  // the motion before the loss says nothing about the motion now
      result.relocalised = true;
    }
  }
  if (!tracking.lost && !result.relocalised && fasterThanThePlatform(tracking.T_ref_cur, result.t_ns)) {
    // A pose sliding along what nothing observes, not the camera: lost, and the slide's velocity with it, so
    // that neither the next guess nor this frame's reported pose continues it.
    tracking.lost = true;
    T_previous_current_ = SE3d();
    T_reference_guess_ = SE3d();
  }
  result.used_reference_fill = !tracking.lost && tracking.reference == ReferencePixels::kMapAndFill;
  result.tracking = tracking.lost ? TrackingState::kLost : TrackingState::kTracked;
  result.icp_inliers = tracking.icp_inliers;
  result.icp_candidates = tracking.icp_candidates;
  result.icp_energy = tracking.icp_energy;
  result.rgb_inliers = tracking.rgb_inliers;
  result.iterations = tracking.iterations;
  if (tracking.lost) {
    // Not fused, so the map stays clean; the pose is the continued motion's guess, and the velocity is kept
    // for the next frame's guess.
    ++rgbd_lost_frames_;
    result.T_W_C = T_W_reference_ * T_reference_guess_;
    return;
  }
  if (rgbd_lost_frames_ == 0) T_previous_current_ = tracking.T_ref_cur;  // only between consecutive frames
  rgbd_lost_frames_ = 0;
  result.T_W_C = T_W_reference_ * tracking.T_ref_cur;
}

void Slam::trackInertial(std::int64_t t_imu_ns, std::span<const ImuSample> imu, FrameResult& result) {
  dense_terms_->setReference(T_W_reference_);
  estimator::FrameSolve solve;
  result.imu_issue =
      estimator_->track(t_imu_ns, imu::bracketingSamples(imu, estimator_->t_ns(), t_imu_ns), dense_terms_.get(), solve);
  if (result.imu_issue) {
    const NavState previous = estimator_->state();
    trackRgbd(result);
    if (result.lost()) {
      // Never restart from a pose nothing verified (dead reckoning from it would not meet the map again): RGB-D
      // tracking carries on from the view tracked last until it holds; process() restarts the estimator there.
      estimator_->stop();
      restart_state_ = previous;
      return;
    }
    startEstimator(t_imu_ns, imu, &previous, result);
    return;
  }
  const TrackingResult& statistics = dense_terms_->statistics();
  result.icp_inliers = statistics.icp_inliers;
  result.icp_candidates = statistics.icp_candidates;
  result.icp_energy = statistics.icp_energy;
  result.rgb_inliers = statistics.rgb_inliers;
  result.iterations = solve.iterations;
  result.imu_chi2 = solve.imu_chi2;
  result.vision_chi2 = solve.vision_chi2;
  result.vision_rejected = solve.vision_rejected;
  const NavState& x = estimator_->state();
  result.T_W_C = SE3d(x.q_W_C, x.r_W_C);
  T_previous_current_ = T_W_reference_.inverse() * result.T_W_C;
  rgbd_lost_frames_ = 0;  // the estimator carries the pose, lost or not
  result.inertial = true;
  result.state = x;
  result.state_variance = estimator_->covarianceDiagonal();
  result.tracking = solve.vision_used ? TrackingState::kTracked : carriedOrLost(result);
  if (result.tracking != TrackingState::kLost) return;
  // Dead reckoning has outgrown the map: look for the place, and restart the estimator there, keeping its
  // velocity, biases and gravity as prior means (as after refused IMU samples).
  TrackingResult tracking;
  SE3d T_W_place;
  if (!relocalise(tracking, T_W_place)) {
    // Neither dead reckoning nor a known place holds: RGB-D tracking takes over from the view tracked against
    // last (the reference stays there), continuing this frame's motion, and process() restarts the estimator at
    // the first pose it verifies.
    restart_state_ = estimator_->state();
    estimator_->stop();
    rgbd_lost_frames_ = 1;
    T_reference_guess_ = T_previous_current_;
    return;
  }
  const NavState previous = estimator_->state();
  result.T_W_C = T_W_place * tracking.T_ref_cur;
  result.tracking = TrackingState::kTracked;
  result.relocalised = true;
  result.pose_sigma_m = 0.0;
  result.icp_inliers = tracking.icp_inliers;
  result.icp_candidates = tracking.icp_candidates;
  result.icp_energy = tracking.icp_energy;
  result.rgb_inliers = tracking.rgb_inliers;
  T_previous_current_ = SE3d();
  startEstimator(t_imu_ns, imu, &previous, result);
}

void Slam::locateInLoadedMap(std::int64_t t_imu_ns, std::span<const ImuSample> imu, FrameResult& result) {
  TrackingResult tracking;
  SE3d T_W_place;
  if (!relocalise(tracking, T_W_place) && !searchMap(t_imu_ns, imu, tracking, T_W_place, result)) {
    result.tracking = TrackingState::kLost;
    result.relocalising = true;
    return;
  }
  relocalising_ = false;
  T_W_reference_ = T_W_place;
  T_previous_current_ = SE3d();
  rgbd_lost_frames_ = 0;
  result.T_W_C = T_W_place * tracking.T_ref_cur;
  result.tracking = TrackingState::kTracked;
  result.relocalised = true;
  result.icp_inliers = tracking.icp_inliers;
  result.icp_candidates = tracking.icp_candidates;
  result.icp_energy = tracking.icp_energy;
  result.rgb_inliers = tracking.rgb_inliers;
  result.iterations = tracking.iterations;
  // The saved surfels in view have aged past the time window while the map was on disk and the camera was
  // being located: active again, this frame fuses into them instead of mapping the place a second time.
  // (Localisation only renders every stable surfel and changes none: nothing to reactivate.)
  if (mapping_) loop_closure_->reactivateInView(result.T_W_C, frame_index_);
  if (estimator_) {
    // The saved gravity direction and biases; the velocity of the saved run's last frame says nothing now.
    std::optional<NavState> start = loaded_state_;
    if (start) start->v_I_S.setZero();
    startEstimator(t_imu_ns, imu, start ? &*start : nullptr, result);
  }
}

bool Slam::relocalise(TrackingResult& tracking, SE3d& T_W_place) {
  if (!relocaliser_) return false;
  const std::optional<PlaceCandidate> place = relocaliser_->candidate();
  if (!place) return false;
  // The map as the keyframe saw it: rendered at its time, surfels updated since the keyframe's time window
  // count as active (what the camera saw then, and what it mapped after), those gone inactive since too.
  prediction_->setView(place->T_W_C.inverse(), place->frame_index);
  predict_only_[map_->current()]->run();
  const TrackingResult at_place = tracker_->track(SE3d(), ReferencePixels::kMap, TrackingGuess::kPlace);
  if (at_place.lost || !tracker_->explainsFrame(at_place)) return false;
  tracking = at_place;
  T_W_place = place->T_W_C;
  place_agreement_ =
      relocaliser_->agreement(*place, T_W_place * at_place.T_ref_cur, prediction_->camera(0), place_depth_gate_m_);
  return true;
}

TrackingState Slam::carriedOrLost(FrameResult& result) const {
  result.pose_sigma_m = PoseVariance::of(result.state_variance).sigmaAt(far_depth_m_);
  return result.pose_sigma_m <= carry_.max_pose_to_depth_sigma * far_depth_sigma_m_ ? TrackingState::kImuCarried
                                                                                    : TrackingState::kLost;
}

void Slam::closeLoop(FrameResult& result) {
  std::optional<Eigen::Vector3d> g_W;
  if (result.inertial) g_W = result.state.q_I_W.conjugate() * Eigen::Vector3d(0.0, 0.0, -gravity_mps2_);
  result.closure = loop_closure_->tryClose(result.T_W_C, frame_index_, g_W);
  if (result.closure.outcome != ClosureOutcome::kAccepted) return;
  if (relocaliser_) {
    relocaliser_->moveKeyframes(
        [&](const SE3d& T_W_C, std::uint32_t frame) { return loop_closure_->deformPose(T_W_C, frame); });
  }
  const SE3d& T_Wnew_Wold = result.closure.T_Wnew_Wold;
  result.T_W_C = T_Wnew_Wold * result.T_W_C;
  T_W_reference_ = result.T_W_C;
  T_W_O_ = T_Wnew_Wold * T_W_O_;
  if (estimator_ && estimator_->initialised()) {
    estimator_->moveWithMap(T_Wnew_Wold);
    result.state = estimator_->state();
  }
  // The next frame's reference: the deformed map at the corrected pose.
  prediction_->setView(T_W_reference_.inverse(), frame_index_);
  predict_only_[map_->current()]->run();
}

void Slam::startEstimator(std::int64_t t_imu_ns, std::span<const ImuSample> imu, const NavState* previous,
                          FrameResult& result) {
  NavState x;
  if (previous != nullptr) x = *previous;
  x.r_W_C = result.T_W_C.translation();
  x.q_W_C = result.T_W_C.quaternion();
  if (previous == nullptr) {
    const std::int64_t window_ns = estimator_->options().gravity_window_ns;
    const std::span<const ImuSample> window = imu::bracketingSamples(imu, t_imu_ns - window_ns, t_imu_ns);
    const auto gravity = estimator::initialGravity(window, result.T_W_C, T_S_C_, static_accel_bias_S_);
    if (!gravity) {  // nothing to start from yet: try again at the next frame
      if (!result.imu_issue)
        result.imu_issue = imu::ImuSampleIssue{imu::ImuSampleProblem::kNoSamples, t_imu_ns, t_imu_ns};
      return;
    }
    x.q_I_W = gravity->q_I_W;
    x.b_a = static_accel_bias_S_;  // the prior's mean; its σ is the IMU noise's accel_bias_prior
  }
  estimator_->initialise(t_imu_ns, x);
  result.inertial = true;
  result.state = estimator_->state();
  result.state_variance = estimator_->covarianceDiagonal();
}

FrameResult Slam::process(const RgbdFrame& frame, std::span<const ImuSample> imu) {
  if (!mapping_ && !map_loaded_) {
    throw Error("localisation only (mapping off) needs a loaded map: Slam::loadMap before the first frame");
  }
  FrameResult result;
  result.t_ns = frame.t_ns;
  const auto start = std::chrono::steady_clock::now();
  tracker_->preprocess(frame);
  if (relocaliser_) relocaliser_->encode(frame);
  result.preprocess_ms = msSince(start);

  const std::int64_t t_imu_ns = frame.t_ns + time_shift_cam_imu_ns_;
  result.T_W_C = T_W_reference_;  // the first frame defines W (identity) and only starts the map
  const auto track_start = std::chrono::steady_clock::now();
  if (relocalising_) {
    locateInLoadedMap(t_imu_ns, imu, result);
  } else if (frame_index_ > first_frame_index_) {
    if (estimator_ && estimator_->initialised()) {
      trackInertial(t_imu_ns, imu, result);
    } else {
      trackRgbd(result);
    }
  }
  result.tracking_ms = msSince(track_start);
  if (estimator_ && !estimator_->initialised() && !relocalising_ && !result.lost()) {
    startEstimator(t_imu_ns, imu, restart_state_ ? &*restart_state_ : nullptr, result);
    if (estimator_->initialised()) restart_state_.reset();
  }
  // The next frame's reference is rendered here, except while RGB-D tracking is lost (trackRgbd).
  if (rgbd_lost_frames_ == 0) {
    T_W_reference_ = result.T_W_C;
    reference_t_ns_ = frame.t_ns;
  }

  const auto map_start = std::chrono::steady_clock::now();
  const SE3d T_C_W = result.T_W_C.inverse();
  const int parity = map_->current();
  prediction_->setView(T_W_reference_.inverse(), frame_index_);
  if (result.lost()) {
    predict_only_[parity]->run();
    result.map_stages = readMapStages(false);
  } else if (!mapping_) {
    // Localisation only: nothing is fused (the map stays as loaded); the tracked frame still completes the
    // reference view the next frame is tracked against.
    update_[parity]->run();
    result.map_stages = readMapStages(true);
    result.map_stages.fusion_ms = result.map_stages.maintenance_ms = -1.0;
    result.coverage = reference_fill_->coverage().share();
  } else {
    map::FusionPoseUncertainty uncertainty;
    if (result.tracking == TrackingState::kImuCarried) {
      const PoseVariance variance = PoseVariance::of(result.state_variance);
      uncertainty = {variance.position_m2, variance.rotation_rad2};
    }
    if (map_loaded_ && result.tracking == TrackingState::kTracked && !result.relocalised) {
      // The loaded map's surfels this frame sees again come back before it is fused, so that it fuses into them
      // instead of mapping the place a second time beside them (the tracker then follows them: the saved map is
      // the reference wherever it reaches). This run's own surfels still return only by a loop closure, which
      // corrects this run's drift first.
      loop_closure_->reactivateInView(result.T_W_C, frame_index_, first_frame_index_);
    }
    fusion_->setFrame(result.T_W_C, frame_index_, uncertainty);
    maintenance_->setView(T_C_W, frame_index_);
    update_[parity]->run();
    result.map_stages = readMapStages(true);
    map_->flip();
    result.map_evicted = maintenance_->stats().evicted_when_full;
    result.coverage = reference_fill_->coverage().share();
  }
  if (loop_closure_ && mapping_ && result.tracking == TrackingState::kTracked && frame_index_ > first_frame_index_) {
    closeLoop(result);
  }
  if (relocaliser_ && mapping_ && result.tracking == TrackingState::kTracked) {
    relocaliser_->offer(result.T_W_C, frame.t_ns, frame_index_);
  }
  const map::MapState state = map_->readState(*arena_);
  result.surfels = state.surfel_count;
  result.active_surfels = state.surfel_count - state.active_begin;
  result.map_overflow = state.overflow_count;
  result.T_W_O = T_W_O_;
  if (result.relocalised) result.place_agreement = place_agreement_;
  result.mapping_ms = msSince(map_start);
  ++frame_index_;
  return result;
}

}  // namespace vifusion::slam
