#include "vifusion/slam/loop_closure.hpp"

#include <chrono>
#include <string>

#include "vifusion/core/error.hpp"
#include "vifusion/core/resident_memory.hpp"

namespace vifusion::slam {
namespace {

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

map::PredictionOptions inactiveOptions(map::PredictionOptions options) {
  options.surfels = map::PredictedSurfels::kInactive;
  return options;
}

}  // namespace

void LoopClosureOptions::validate() const {
  registration.validate();
  graph.validate();
  if (constraint_grid_step_px < 1) throw Error("loop closure option 'constraint_grid_step_px' must be ≥ 1");
  if (!(max_constraint_error_m > 0.0)) throw Error("loop closure option 'max_constraint_error_m' must be > 0");
}

const char* closureOutcomeName(ClosureOutcome outcome) {
  switch (outcome) {
    case ClosureOutcome::kAccepted:
      return "accepted";
    case ClosureOutcome::kRefused:
      return "refused";
    case ClosureOutcome::kAgreed:
      return "agreed";
    case ClosureOutcome::kNone:
      break;
  }
  return "none";
}

const char* closureRefusalName(ClosureRefusal refusal) {
  switch (refusal) {
    case ClosureRefusal::kNone:
      return "none";
    case ClosureRefusal::kOverlap:
      return "overlap";
    case ClosureRefusal::kDiverged:
      return "diverged";
    case ClosureRefusal::kResidual:
      return "residual";
    case ClosureRefusal::kUnconstrained:
      return "unconstrained";
    case ClosureRefusal::kCovariance:
      return "covariance";
    case ClosureRefusal::kCorrection:
      return "correction";
    case ClosureRefusal::kSolve:
      return "solve";
    case ClosureRefusal::kConsistency:
      return "consistency";
    case ClosureRefusal::kAmbiguous:
      return "ambiguous";
  }
  return "unknown";
}

namespace {

ClosureRefusal refusalOf(RegistrationVerdict verdict) {
  switch (verdict) {
    case RegistrationVerdict::kAccepted:
      return ClosureRefusal::kNone;
    case RegistrationVerdict::kNoOverlap:
      return ClosureRefusal::kOverlap;
    case RegistrationVerdict::kDiverged:
      return ClosureRefusal::kDiverged;
    case RegistrationVerdict::kResidual:
      return ClosureRefusal::kResidual;
    case RegistrationVerdict::kUnconstrained:
      return ClosureRefusal::kUnconstrained;
    case RegistrationVerdict::kCovariance:
      return ClosureRefusal::kCovariance;
    case RegistrationVerdict::kCorrection:
      return ClosureRefusal::kCorrection;
    case RegistrationVerdict::kAmbiguous:
      return ClosureRefusal::kAmbiguous;
  }
  return ClosureRefusal::kDiverged;
}

}  // namespace

LoopClosure::LoopClosure(gpu::GpuContext& context, gpu::CapacityPlan& plan, const map::MapBuffers& map,
                         const map::ModelPrediction& prediction, const map::PredictionOptions& prediction_options,
                         const map::FusionOptions& fusion, const tracking::IcpOptions& icp, double far_depth_m,
                         const LoopClosureOptions& options)
    : context_(context), map_(map), active_(prediction), options_(options) {
  options_.validate();
  const PinholeCamera& camera = prediction.camera(0);
  inactive_ = std::make_unique<map::ModelPrediction>(context, plan, map, camera, inactiveOptions(prediction_options));
  registration_ =
      std::make_unique<ModelRegistration>(context, plan, prediction.levels(), icp, far_depth_m, options_.registration);
  for (int y = options_.constraint_grid_step_px / 2; y < camera.height; y += options_.constraint_grid_step_px) {
    for (int x = options_.constraint_grid_step_px / 2; x < camera.width; x += options_.constraint_grid_step_px) {
      grid_.push_back({x, y});
    }
  }
  map::MapSamplingOptions sampling;
  sampling.max_nodes = static_cast<std::uint32_t>(options_.graph.max_nodes);
  sampling.max_points = static_cast<std::uint32_t>(grid_.size());
  sampling_ = std::make_unique<map::MapSampling>(context, plan, map, sampling);
  active_gather_ = std::make_unique<map::PredictionGather>(context, plan, map, prediction, sampling);
  inactive_gather_ = std::make_unique<map::PredictionGather>(context, plan, map, *inactive_, sampling);
  map::SurfelDeformationOptions deformation;
  deformation.max_nodes = static_cast<std::uint32_t>(options_.graph.max_nodes);
  deformation.candidates = static_cast<std::uint32_t>(options_.graph.candidates);
  deformation_ = std::make_unique<map::SurfelDeformation>(context, plan, map, deformation);
  reactivation_ = std::make_unique<map::SurfelReactivation>(context, plan, map, *inactive_, fusion);
  if (options_.graph.max_constraints < static_cast<int>(2 * grid_.size())) {
    options_.graph.max_constraints = static_cast<int>(2 * grid_.size());  // a constraint and a pin per grid point
  }
  graph_ = std::make_unique<loop::DeformationGraph>(options_.graph);
  resizeResident(node_samples_, static_cast<std::size_t>(options_.graph.max_nodes), loop::NodeSample{});
}

LoopClosure::~LoopClosure() = default;

void LoopClosure::build(const gpu::MemoryArena& arena) {
  inactive_->build(arena);
  std::vector<RegistrationLevel> levels;
  for (int l = 0; l < active_.levels(); ++l) {
    levels.push_back({active_.camera(l), active_.level(l).vertices, active_.level(l).normals,
                      inactive_->level(l).vertices, inactive_->level(l).normals});
  }
  registration_->build(arena, levels);
  sampling_->build(arena);
  active_gather_->build(arena);
  inactive_gather_->build(arena);
  active_gather_->setPixels(grid_);
  inactive_gather_->setPixels(grid_);
  deformation_->build(arena);
  reactivation_->build(arena);
  for (int parity = 0; parity < 2; ++parity) {
    render_inactive_[parity] = gpu::CommandSequence::create(context_, "loop.inactive" + std::to_string(parity));
    render_inactive_[parity]->record([&](gpu::CommandRecorder& recorder) {
      recorder.computeBarrier();
      inactive_->record(recorder, parity);
      recorder.hostReadBarrier();
    });
  }
  // Every kernel runs once now, on the empty map: a driver that compiles pipelines on first use (lavapipe's
  // LLVM) does it at start-up, not in the SLAM thread at the first closure.
  inactive_->setView(SE3d(), 0);
  render_inactive_[map_.current()]->run();
  registration_->align();
  sampling_->sample();
  active_gather_->gather();
  inactive_gather_->gather();
  map::DeformationNode identity;
  for (int c = 0; c < 3; ++c) {
    identity.columns[c] = Eigen::Vector4f::Unit(c);
    identity.inverse_transpose_columns[c] = Eigen::Vector4f::Unit(c);
  }
  deformation_->setNodes(std::span<const map::DeformationNode>(&identity, 1));
  deformation_->apply();
  reactivation_->apply();
}

void LoopClosure::reactivateInView(const SE3d& T_W_C, std::uint32_t frame, std::uint32_t created_before) {
  map::SurfelSelection selection;
  selection.surfels = map::PredictedSurfels::kInactive;
  selection.created_before = created_before;
  inactive_->setView(T_W_C.inverse(), frame, selection);
  render_inactive_[map_.current()]->run();
  reactivation_->apply();
}

ClosureReport LoopClosure::tryClose(const SE3d& T_W_C, std::uint32_t frame, const std::optional<Eigen::Vector3d>& g_W) {
  ClosureReport report;
  const std::uint32_t first_frame = options_.first_frame > 0 ? options_.first_frame : map_.options().time_window_frames;
  if (frame < first_frame) return report;
  const auto start = std::chrono::steady_clock::now();
  inactive_->setView(T_W_C.inverse(), frame);
  render_inactive_[map_.current()]->run();
  report.registration = registration_->align();
  report.registration_ms = msSince(start);
  if (report.registration.verdict == RegistrationVerdict::kNoOverlap && report.registration.iterations == 0) {
    report.ms = msSince(start);
    return report;  // nothing inactive in view: not an attempt
  }
  if (!report.registration.accepted()) {
    report.outcome = ClosureOutcome::kRefused;
    report.refusal = refusalOf(report.registration.verdict);
    report.ms = msSince(start);
    return report;
  }
  if (!report.registration.significant) {
    // The inactive prediction rendered for the registration is at this very pose: its surfels are the ones
    // in view.
    const auto apply_start = std::chrono::steady_clock::now();
    reactivation_->apply();
    report.apply_ms = msSince(apply_start);
    report.outcome = ClosureOutcome::kAgreed;
    report.ms = msSince(start);
    return report;
  }
  report = deform(T_W_C, frame, g_W, report);
  report.ms = msSince(start);
  return report;
}

ClosureReport LoopClosure::deform(const SE3d& T_W_C, std::uint32_t frame, const std::optional<Eigen::Vector3d>& g_W,
                                  ClosureReport report) {
  const auto start = std::chrono::steady_clock::now();
  sampling_->sample();
  const std::size_t nodes = sampling_->readNodeSamples(node_samples_);
  graph_->build(std::span<const loop::NodeSample>(node_samples_.data(), nodes), last_accepted_frame_);
  graph_->setGravity(options_.gravity_term && g_W ? *g_W : Eigen::Vector3d::Zero());
  report.nodes = graph_->nodeCount();

  // The active surfels mapped since the last accepted closure go where the registration puts them:
  // p' = T_W_C·T_inactive_active·T_C_W·p. Older active ones were corrected by that closure (or reactivated by it
  // from the old map) and stay, as their nodes do (graph build above).
  active_gather_->gather();
  inactive_gather_->gather();
  const SE3d T_correction = T_W_C * report.registration.T_inactive_active * T_W_C.inverse();
  for (const map::GatheredPoint& p : active_gather_->points()) {
    if (!p.valid) continue;
    const Eigen::Vector3d source = p.position().cast<double>();
    if (p.created_frame >= last_accepted_frame_) {
      graph_->addConstraint(source, p.created_frame, T_correction * source);
    } else {
      graph_->addPin(source, p.created_frame);
    }
  }
  for (const map::GatheredPoint& q : inactive_gather_->points()) {
    if (!q.valid) continue;
    graph_->addPin(q.position().cast<double>(), q.created_frame);
  }
  report.constraints = graph_->constraintCount();
  const loop::DeformationSolveResult solve = graph_->solve();
  report.deformation_ms = msSince(start);
  report.constraint_error_before_m = solve.mean_constraint_error_before_m;
  report.constraint_error_after_m = solve.mean_constraint_error_after_m;
  if (!solve.hasSolution()) {
    graph_->revert();
    report.outcome = ClosureOutcome::kRefused;
    report.refusal = ClosureRefusal::kSolve;
    return report;
  }
  if (!(solve.mean_constraint_error_after_m <= options_.max_constraint_error_m)) {
    graph_->revert();
    report.outcome = ClosureOutcome::kRefused;
    report.refusal = ClosureRefusal::kConsistency;
    return report;
  }
  graph_->commit();
  const auto apply_start = std::chrono::steady_clock::now();
  deformation_->setNodes(*graph_);
  deformation_->apply();
  report.T_Wnew_Wold = graph_->deformPose(T_W_C, frame) * T_W_C.inverse();
  // The inactive surfels now in view at the corrected pose become active again.
  const SE3d T_W_C_new = report.T_Wnew_Wold * T_W_C;
  inactive_->setView(T_W_C_new.inverse(), frame);
  render_inactive_[map_.current()]->run();
  reactivation_->apply();
  last_accepted_frame_ = frame;
  report.apply_ms = msSince(apply_start);
  report.outcome = ClosureOutcome::kAccepted;
  return report;
}

SE3d LoopClosure::deformPose(const SE3d& T_W_C, std::uint32_t frame) const {
  return graph_->nodeCount() > 0 ? graph_->deformPose(T_W_C, frame) : T_W_C;
}

}  // namespace vifusion::slam
