#include "vifusion/slam/rgbd_slam.hpp"

#include <chrono>
#include <string>

#include "vifusion/core/error.hpp"

namespace vifusion::slam {
namespace {

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

void SlamOptions::validate() const {
  tracker.validate();
  map.validate();
  fusion.validate();
  maintenance.validate();
  prediction.validate();
}

RgbdSlam::RgbdSlam(gpu::GpuContext& context, const RigCalibration& calibration, const SlamOptions& options) {
  options.validate();
  const PinholeCamera& camera = calibration.camera;
  tracker_ = std::make_unique<DenseTracker>(context, plan_, camera, calibration.depth_scale_m, options.tracker);
  map_ = std::make_unique<map::MapBuffers>(plan_, options.map, camera);
  fusion_ = std::make_unique<map::SurfelFusion>(context, plan_, *map_, camera, options.fusion);
  maintenance_ = std::make_unique<map::MapMaintenance>(context, plan_, *map_, camera, options.maintenance);
  map::PredictionOptions prediction = options.prediction;
  prediction.levels = options.tracker.levels;
  prediction_ = std::make_unique<map::ModelPrediction>(context, plan_, *map_, camera, prediction);
  exporter_ = std::make_unique<map::MapExport>(context, plan_, *map_);

  arena_ = gpu::MemoryArena::create(context, plan_);
  tracker_->build(*arena_);
  fusion_->build(*arena_, map::FusionInputs::fromPreprocess(tracker_->preprocessing()));
  maintenance_->build(*arena_);
  prediction_->build(*arena_);
  exporter_->build(*arena_);
  map_->reset(*arena_);
  for (int parity = 0; parity < 2; ++parity) {
    update_[parity] = gpu::CommandSequence::create(context, "slam.update" + std::to_string(parity));
    update_[parity]->record([&](gpu::CommandRecorder& recorder) { recordMapUpdate(recorder, parity, true); });
    predict_only_[parity] = gpu::CommandSequence::create(context, "slam.predict" + std::to_string(parity));
    predict_only_[parity]->record([&](gpu::CommandRecorder& recorder) { recordMapUpdate(recorder, parity, false); });
  }
}

RgbdSlam::~RgbdSlam() = default;

// Fusion reads surfel array `parity` and the compaction writes the survivors to the other one, which
// the prediction renders. The predicted maps are then copied into the tracker's reference view.
void RgbdSlam::recordMapUpdate(gpu::CommandRecorder& recorder, int parity, bool fuse) const {
  int predicted_parity = parity;
  if (fuse) {
    fusion_->record(recorder, parity);
    recorder.computeBarrier();
    maintenance_->record(recorder, parity);
    recorder.computeBarrier();
    predicted_parity = parity ^ 1;
  }
  prediction_->record(recorder, predicted_parity);
  for (int l = 0; l < prediction_->levels(); ++l) {
    const map::ModelLevelBuffers& model = prediction_->level(l);
    const preprocess::LevelBuffers& reference = tracker_->reference(l);
    for (auto [from, to] : {std::pair{model.vertices, reference.vertices}, std::pair{model.normals, reference.normals}}) {
      recorder.copyBuffer(arena_->buffer(from), arena_->buffer(to), arena_->buffer(from).bytes);
    }
  }
  const gpu::GpuBuffer& model_intensity = arena_->buffer(prediction_->level(0).intensity);
  recorder.copyBuffer(model_intensity, arena_->buffer(tracker_->reference(0).intensity), model_intensity.bytes);
  recorder.computeBarrier();
  tracker_->recordReferenceIntensity(recorder);
  recorder.hostReadBarrier();
}

FrameResult RgbdSlam::process(const RgbdFrame& frame) {
  FrameResult result;
  result.t_ns = frame.t_ns;
  const auto start = std::chrono::steady_clock::now();
  tracker_->preprocess(frame);
  result.preprocess_ms = msSince(start);

  if (frame_index_ > 0) {  // the first frame defines W and only starts the map
    const auto track_start = std::chrono::steady_clock::now();
    const TrackingResult tracking = tracker_->track(T_previous_current_);
    result.tracking_ms = msSince(track_start);
    result.lost = tracking.lost;
    result.icp_inliers = tracking.icp_inliers;
    result.icp_candidates = tracking.icp_candidates;
    result.rgb_inliers = tracking.rgb_inliers;
    result.iterations = tracking.iterations;
    // A lost frame keeps the constant-velocity guess for itself and is not fused, so the map stays
    // clean; the velocity is then reset, so a run of lost frames stops instead of drifting away.
    T_W_previous_ = T_W_previous_ * tracking.T_ref_cur;
    T_previous_current_ = tracking.lost ? SE3d() : tracking.T_ref_cur;
  }
  result.T_W_C = T_W_previous_;

  const auto map_start = std::chrono::steady_clock::now();
  const SE3d T_C_W = result.T_W_C.inverse();
  const int parity = map_->current();
  prediction_->setView(T_C_W, frame_index_);
  if (result.lost) {
    predict_only_[parity]->run();
  } else {
    fusion_->setFrame(result.T_W_C, frame_index_);
    maintenance_->setView(T_C_W, frame_index_);
    update_[parity]->run();
    map_->flip();
  }
  const map::MapState state = map_->readState(*arena_);
  result.surfels = state.surfel_count;
  result.map_overflow = state.overflow_count;
  result.mapping_ms = msSince(map_start);
  ++frame_index_;
  return result;
}

}  // namespace vifusion::slam
