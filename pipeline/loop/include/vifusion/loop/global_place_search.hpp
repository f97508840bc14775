#pragma once
// Where in a saved map a frame can be, when no keyframe recognises it: a camera entering a saved map along another
// path than the one that built it sees its surfaces from places no keyframe was taken at (sim:living_room_1 starts
// 1.1 m and more from every pose of living_room_0 looking the same way), and dense alignment from a keyframe's
// pose converges only within max_place_correction_m/_rad (dense_tracker.hpp).
//
// With the map's gravity direction known (the saved estimator's q_I_W) and the camera's measured by the
// accelerometer, a camera pose has four free parameters: position and yaw about "up". The search scores the frame's
// block points (fern_image.hpp's block means, back-projected) against the map's distance field
// (surface_distance_field.hpp) at every pose of a grid over the map — positions within the saved camera heights
// and clear of the surfaces, yaws all round — by the truncated mean squared distance (a robust point-to-surface
// ICP energy, evaluated globally). The grid's steps are the dense verification's own basin (the caller passes
// max_place_correction_m/_rad), so the true pose has a grid pose within it. The best grid poses are refined by
// Gauss-Newton on the field in all six parameters (the accelerometer's tilt is only as good as the camera was
// still), the truncation shrinking from the grid step to the ICP's association gate, and the distinct best are
// returned for the caller's dense verification against the map itself.
//
// Cost: grid poses × coarse_points field lookups (early-terminated once a pose cannot enter the best
// refined_poses), then refined_poses × refine_iterations × all points. Everything is allocated at construction;
// search() allocates nothing.

#include <Eigen/Core>
#include <span>
#include <vector>

#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/loop/fern_image.hpp"
#include "vifusion/loop/surface_distance_field.hpp"

namespace vifusion::loop {

struct GlobalSearchOptions {
  /// Frame points scored at every grid pose, spread evenly over the frame's valid blocks (all when fewer). More
  /// separates close grid poses better at a proportional cost. [8, 65536].
  int coarse_points = 256;
  /// Best grid poses refined on the field. Several grid poses fall within one true pose's basin, so this must
  /// exceed `hypotheses` by enough to keep distinct places. [hypotheses, 4096].
  int refined_poses = 48;
  /// Distinct hypotheses returned, best first: what the caller verifies densely. [1, 64].
  int hypotheses = 4;
  /// Gauss-Newton iterations of one refinement. [1, 100].
  int refine_iterations = 12;

  /// @throws vifusion::Error naming the field out of range.
  void validate() const;
};

/// Where the search looks, in the map's terms (the caller derives each from the map and the tracker's options).
struct SearchSpace {
  Eigen::Vector3d up_W = Eigen::Vector3d::UnitZ();  ///< against gravity in W, unit
  double min_height_m = 0.0;  ///< camera centres' range along up_W [m] (the saved cameras' heights, widened)
  double max_height_m = 0.0;
  double position_step_m = 0.3;    ///< grid spacing [m], > 0: the dense verification's translation basin
  double yaw_step_rad = 0.2;       ///< yaw spacing [rad], in (0, π]: its rotation basin
  double min_clearance_m = 0.2;    ///< a camera centre is at least this far from every surface [m], ≥ 0
  double inlier_distance_m = 0.1;  ///< a point within this of a surface agrees [m], > 0: the ICP's gate

  /// @throws vifusion::Error naming the field out of range.
  void validate() const;
};

struct PlaceHypothesis {
  SE3d T_W_C;
  /// Mean over the frame's points of min(d², τ²)/τ² with d the distance to the map's surfaces and τ the inlier
  /// distance, in [0, 1]: 0 when every point lies on a surface, 1 when none is near one.
  double cost = 1.0;
  double inlier_share = 0.0;  ///< share of the frame's points within the inlier distance of a surface
};

/// The camera-frame points of a block image's valid blocks (block centres back-projected at their mean depth, as
/// keyframe_agreement.hpp does), at most out.size(); returns how many were written. No allocation.
int blockPoints(const FernImage& image, const PinholeCamera& input_camera, int factor, std::span<Eigen::Vector3d> out);

/// The residual of one point in the search's refinement: the field's distance at T_W_C·p_C, and its Jacobian
/// over a left perturbation T_W_C ← exp(δ)·T_W_C, δ = [ρ; φ] (se3.hpp). Infinity (and no Jacobian) off the grid.
double fieldResidual(const SurfaceDistanceField& field, const SE3d& T_W_C, const Eigen::Vector3d& p_C,
                     Eigen::Matrix<double, 1, 6>* J = nullptr);

class GlobalPlaceSearch {
 public:
  /// Takes the map's field; lays out the grid's positions (those within the heights and clear of the surfaces)
  /// and the buffers for frames of up to max_points points. Allocates.
  /// @throws vifusion::Error naming what is out of range, or when no grid position is clear of the map
  GlobalPlaceSearch(SurfaceDistanceField field, const SearchSpace& space, const GlobalSearchOptions& options,
                    int max_points);

  /// The distinct best poses for a frame's points (camera frame, at most max_points; fewer than 3 gives none)
  /// whose camera measures "up" (against gravity) along up_C; best (lowest cost) first. The span lives until the
  /// next call. No allocation.
  std::span<const PlaceHypothesis> search(std::span<const Eigen::Vector3d> points_C, const Eigen::Vector3d& up_C);

  /// The cost and inlier share of points_C at T_W_C (PlaceHypothesis's definitions). No allocation.
  PlaceHypothesis evaluate(std::span<const Eigen::Vector3d> points_C, const SE3d& T_W_C) const;

  /// Whether two poses are one place: within one grid step and one yaw step (the dense verification's basin).
  bool samePlace(const SE3d& a, const SE3d& b) const;

  const SurfaceDistanceField& field() const { return field_; }
  std::size_t gridPositions() const { return positions_W_.size(); }
  int gridYaws() const { return yaws_; }

 private:
  struct Scored {
    SE3d T_W_C;
    double cost = 1.0;
  };
  /// Gauss-Newton on the field from `T_W_C`.
  SE3d refine(std::span<const Eigen::Vector3d> points_C, SE3d T_W_C) const;

  SurfaceDistanceField field_;
  SearchSpace space_;
  GlobalSearchOptions options_;
  int max_points_ = 0;
  int yaws_ = 0;
  std::vector<Eigen::Vector3d> positions_W_;  ///< grid camera centres clear of the surfaces
  std::vector<Eigen::Vector3d> coarse_C_;     ///< the subsampled points, then rotated per yaw
  std::vector<Eigen::Vector3d> rotated_;
  std::vector<Scored> best_;  ///< the best grid poses so far, sorted by cost
  std::vector<PlaceHypothesis> refined_;
  std::vector<PlaceHypothesis> hypotheses_;
};

}  // namespace vifusion::loop
