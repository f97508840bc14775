// Slam::prepareMapSearch and Slam::searchMap (slam.hpp): entering a saved map where no keyframe recognises the view.
#include <algorithm>
#include <cmath>
#include <limits>

#include "vifusion/estimator/gravity_initialisation.hpp"
#include "vifusion/imu/sample_window.hpp"
#include "vifusion/slam/slam.hpp"

namespace vifusion::slam {
namespace {

/// A place proposed by the geometry alone must also agree in colour: of the pixels the ICP associates with the
/// map there, most (this share) must be photometric inliers too (within the photometric term's Huber bound of
/// the intensity noise). At the right place nearly all do, less those where the map's colour or the frame's is
/// off; a place of the same shape elsewhere — a room's other corner — has the geometry and not the colours.
constexpr double kMinPhotometricShareOfIcpInliers = 0.5;

/// ... and fit the map's surfaces as closely as two measurements of one surface do: the ICP's mean normalised
/// squared residual (TrackingResult::icp_energy, in units of the frame's depth noise σ_z²) at most what a frame
/// and a model that each measure the surface to σ_z give in expectation, σ_z² + σ_z². An alignment that settled
/// beside the place (partly overlapping surfaces, a slide along a wall) keeps residuals of centimetres.
constexpr double kMaxIcpEnergyOfOneSurface = 2.0;

/// ... and the map must explain most of the frame: this share of its block points within the ICP's association
/// gate of a saved surface at the verified pose. Where the map holds less of the view, the part it does hold (a
/// wall, a corner) fits many places, and nothing in the rest says which.
constexpr double kMinExplainedShare = 0.5;

}  // namespace

void Slam::prepareMapSearch(std::span<const Eigen::Vector3f> surfaces_W,
                            std::span<const mapfile::StampedPose> trajectory, const NavState& state) {
  const TrackerOptions& tracker = tracker_->options();
  loop::SearchSpace space;
  space.up_W = (state.q_I_W.conjugate() * Eigen::Vector3d::UnitZ()).normalized();
  // The verification's basin sets the grid, so that the true pose has a grid pose within it.
  space.position_step_m = tracker.max_place_correction_m;
  space.yaw_step_rad = tracker.max_place_correction_rad;
  space.min_clearance_m = min_depth_m_;
  space.inlier_distance_m = place_depth_gate_m_;
  // The saved cameras' heights, one grid step wider on each side: a camera entering the map is carried as the
  // one that built it was (a robot's is fixed; a hand-held one's varies by centimetres to decimetres).
  double lowest = std::numeric_limits<double>::infinity(), highest = -lowest;
  for (const mapfile::StampedPose& pose : trajectory) {
    const double height = space.up_W.dot(pose.T_W_C.translation());
    lowest = std::min(lowest, height);
    highest = std::max(highest, height);
  }
  if (trajectory.empty()) lowest = highest = 0.0;
  space.min_height_m = lowest - space.position_step_m;
  space.max_height_m = highest + space.position_step_m;
  const loop::FernImage& image = relocaliser_->frameImage();
  const int max_points = image.width() * image.height();
  map_search_ =
      std::make_unique<loop::GlobalPlaceSearch>(loop::SurfaceDistanceField(surfaces_W, relocalisation_.distance_field),
                                                space, relocalisation_.search, max_points);
  map_search_points_.assign(static_cast<std::size_t>(max_points), Eigen::Vector3d::Zero());
}

bool Slam::searchMap(std::int64_t t_imu_ns, std::span<const ImuSample> imu, TrackingResult& tracking, SE3d& T_W_place,
                     FrameResult& result) {
  if (!map_search_) return false;
  // "Up" in the camera: the accelerometer's mean over the gravity window, as the estimator's start takes it
  // (W = C here, so its q_I_W is q_I_C).
  const std::int64_t window_ns = estimator_->options().gravity_window_ns;
  const auto gravity = estimator::initialGravity(imu::bracketingSamples(imu, t_imu_ns - window_ns, t_imu_ns), SE3d(),
                                                 T_S_C_, static_accel_bias_S_);
  if (!gravity) return false;
  const Eigen::Vector3d up_C = gravity->q_I_W.conjugate() * Eigen::Vector3d::UnitZ();
  const int n = loop::blockPoints(relocaliser_->frameImage(), prediction_->camera(0), relocaliser_->downsampleFactor(),
                                  map_search_points_);
  const std::span<const Eigen::Vector3d> points = std::span<const Eigen::Vector3d>(map_search_points_).first(n);
  const std::span<const loop::PlaceHypothesis> hypotheses = map_search_->search(points, up_C);
  result.map_search_hypotheses = static_cast<int>(hypotheses.size());
  if (hypotheses.empty()) return false;
  result.map_search_cost = hypotheses.front().cost;
  result.map_search_inliers = hypotheses.front().inlier_share;
  // Every stable surfel, whatever its age: the saved map as a whole, not one time of it.
  map::SurfelSelection every_stable;
  every_stable.surfels = map::PredictedSurfels::kStable;
  std::optional<SE3d> located;  // the first verified place's camera
  for (const loop::PlaceHypothesis& hypothesis : hypotheses) {
    prediction_->setView(hypothesis.T_W_C.inverse(), frame_index_, every_stable);
    predict_only_[map_->current()]->run();
    const TrackingResult at = tracker_->track(SE3d(), ReferencePixels::kMap, TrackingGuess::kPlace);
    if (at.lost || !tracker_->explainsFrame(at)) continue;
    if (at.rgb_inliers < kMinPhotometricShareOfIcpInliers * at.icp_inliers) continue;
    if (!(at.icp_energy <= kMaxIcpEnergyOfOneSurface)) continue;
    const SE3d T_W_C = hypothesis.T_W_C * at.T_ref_cur;
    if (map_search_->evaluate(points, T_W_C).inlier_share < kMinExplainedShare) continue;
    if (located) {
      if (!map_search_->samePlace(*located, T_W_C)) ++result.map_search_verified;
      continue;
    }
    ++result.map_search_verified;
    located = T_W_C;
    tracking = at;
    T_W_place = hypothesis.T_W_C;
  }
  return result.map_search_verified == 1;
}

}  // namespace vifusion::slam
