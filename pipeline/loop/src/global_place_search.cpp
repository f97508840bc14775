#include "vifusion/loop/global_place_search.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "vifusion/core/error.hpp"

namespace vifusion::loop {
namespace {

void require(bool ok, const char* what, const char* name, double value, const char* condition) {
  if (!ok || !std::isfinite(value)) {
    throw Error(std::string(what) + " '" + name + "' = " + std::to_string(value) + " must be " + condition);
  }
}

/// Each refinement iteration halves the truncation, from the grid step down to the inlier distance: the grid
/// pose is up to a step off, so at first the points a step away must still pull, and at the end only those
/// within the ICP's gate, as in the dense verification that follows.
constexpr double kTruncationShrink = 0.5;

/// Smallest number of points within the truncation for a Gauss-Newton step: six parameters need six
/// independent residuals at the very least.
constexpr int kMinStepPoints = 6;

}  // namespace

void GlobalSearchOptions::validate() const {
  const char* what = "global place search option";
  require(coarse_points >= 8 && coarse_points <= 65536, what, "coarse_points", coarse_points, "in [8, 65536]");
  require(hypotheses >= 1 && hypotheses <= 64, what, "hypotheses", hypotheses, "in [1, 64]");
  require(refined_poses >= hypotheses && refined_poses <= 4096, what, "refined_poses", refined_poses,
          "in [hypotheses, 4096]");
  require(refine_iterations >= 1 && refine_iterations <= 100, what, "refine_iterations", refine_iterations,
          "in [1, 100]");
}

void SearchSpace::validate() const {
  const char* what = "global place search";
  require(std::abs(up_W.norm() - 1.0) < 1e-6, what, "up_W", up_W.norm(), "a unit vector");
  require(min_height_m <= max_height_m, what, "min_height_m", min_height_m, "<= max_height_m");
  require(std::isfinite(max_height_m), what, "max_height_m", max_height_m, "finite");
  require(position_step_m > 0.0, what, "position_step_m", position_step_m, "> 0");
  require(yaw_step_rad > 0.0 && yaw_step_rad <= std::numbers::pi, what, "yaw_step_rad", yaw_step_rad, "in (0, pi]");
  require(min_clearance_m >= 0.0, what, "min_clearance_m", min_clearance_m, ">= 0");
  require(inlier_distance_m > 0.0, what, "inlier_distance_m", inlier_distance_m, "> 0");
}

int blockPoints(const FernImage& image, const PinholeCamera& input_camera, int factor, std::span<Eigen::Vector3d> out) {
  const double half_block = 0.5 * (factor - 1);
  int n = 0;
  for (int v = 0; v < image.height(); ++v) {
    for (int u = 0; u < image.width(); ++u) {
      const double z = image.depth_m(u, v);
      if (!(z > 0.0)) continue;
      if (n == static_cast<int>(out.size())) return n;
      out[n++] = input_camera.backProject({u * factor + half_block, v * factor + half_block}, z);
    }
  }
  return n;
}

double fieldResidual(const SurfaceDistanceField& field, const SE3d& T_W_C, const Eigen::Vector3d& p_C,
                     Eigen::Matrix<double, 1, 6>* J) {
  Eigen::Vector3d gradient;
  const double d = field.distance(T_W_C * p_C, J != nullptr ? &gradient : nullptr);
  if (J != nullptr && std::isfinite(d)) *J = gradient.transpose() * T_W_C.pointJacobianLeft(p_C);
  return d;
}

GlobalPlaceSearch::GlobalPlaceSearch(SurfaceDistanceField field, const SearchSpace& space,
                                     const GlobalSearchOptions& options, int max_points)
    : field_(std::move(field)), space_(space), options_(options), max_points_(max_points) {
  space.validate();
  options.validate();
  if (field_.empty()) throw Error("global place search: the map's distance field is empty");
  if (max_points < 3) throw Error("global place search: max_points " + std::to_string(max_points) + " must be >= 3");
  yaws_ = static_cast<int>(std::ceil(2.0 * std::numbers::pi / space.yaw_step_rad - 1e-9));
  // A gravity-aligned frame: up and two horizontal axes; the grid spans the field's box projected onto them.
  const Eigen::Vector3d& up = space.up_W;
  const Eigen::Vector3d east = up.unitOrthogonal();
  const Eigen::Vector3d north = up.cross(east);
  const Eigen::Vector3d lo = field_.minCorner(), hi = field_.maxCorner();
  Eigen::Vector2d box_min = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d box_max = -box_min;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d c((corner & 1) ? hi.x() : lo.x(), (corner & 2) ? hi.y() : lo.y(),
                            (corner & 4) ? hi.z() : lo.z());
    const Eigen::Vector2d e(c.dot(east), c.dot(north));
    box_min = box_min.cwiseMin(e);
    box_max = box_max.cwiseMax(e);
  }
  const double step = space.position_step_m;
  for (double h = space.min_height_m; h <= space.max_height_m + 1e-9; h += step) {
    for (double a = box_min.x(); a <= box_max.x(); a += step) {
      for (double b = box_min.y(); b <= box_max.y(); b += step) {
        const Eigen::Vector3d p = a * east + b * north + h * up;
        const double clearance_m = field_.distance(p);  // infinity off the grid: no map to look at from there
        if (clearance_m >= space.min_clearance_m && std::isfinite(clearance_m)) positions_W_.push_back(p);
      }
    }
  }
  if (positions_W_.empty()) {
    throw Error("global place search: no camera position within the saved heights is clear of the map's surfaces");
  }
  coarse_C_.resize(options.coarse_points);
  rotated_.resize(options.coarse_points);
  best_.resize(options.refined_poses);
  refined_.resize(options.refined_poses);
  hypotheses_.resize(options.hypotheses);
}

bool GlobalPlaceSearch::samePlace(const SE3d& a, const SE3d& b) const {
  const SE3d delta = a.inverse() * b;
  return delta.translation().norm() <= space_.position_step_m &&
         Eigen::AngleAxisd(delta.quaternion()).angle() <= space_.yaw_step_rad;
}

PlaceHypothesis GlobalPlaceSearch::evaluate(std::span<const Eigen::Vector3d> points_C, const SE3d& T_W_C) const {
  PlaceHypothesis result;
  result.T_W_C = T_W_C;
  if (points_C.empty()) return result;
  const double tau2 = space_.inlier_distance_m * space_.inlier_distance_m;
  double sum = 0.0;
  int inliers = 0;
  for (const Eigen::Vector3d& p_C : points_C) {
    const double d = field_.distance(T_W_C * p_C);
    if (d < space_.inlier_distance_m) ++inliers;
    sum += std::min(d * d, tau2);
  }
  result.cost = sum / (tau2 * static_cast<double>(points_C.size()));
  result.inlier_share = static_cast<double>(inliers) / static_cast<double>(points_C.size());
  return result;
}

SE3d GlobalPlaceSearch::refine(std::span<const Eigen::Vector3d> points_C, SE3d T_W_C) const {
  double tau = space_.position_step_m;
  for (int iteration = 0; iteration < options_.refine_iterations; ++iteration) {
    Matrix6d H = Matrix6d::Zero();
    Vector6d g = Vector6d::Zero();
    int used = 0;
    for (const Eigen::Vector3d& p_C : points_C) {
      Eigen::Matrix<double, 1, 6> J;
      const double d = fieldResidual(field_, T_W_C, p_C, &J);
      if (!(d < tau)) continue;  // truncated: beyond the current truncation a point is an outlier
      H.noalias() += J.transpose() * J;
      g.noalias() += J.transpose() * d;
      ++used;
    }
    if (used < kMinStepPoints) break;
    // A plane leaves directions unconstrained; the small ridge keeps the solve defined there (units m², rad²).
    H.diagonal().array() += 1e-9 * H.trace();
    Vector6d delta = -H.ldlt().solve(g);
    if (!delta.allFinite()) break;
    // One step moves at most what the current truncation can see.
    const double scale = std::min({1.0, tau / std::max(delta.head<3>().norm(), 1e-12),
                                   space_.yaw_step_rad / std::max(delta.tail<3>().norm(), 1e-12)});
    T_W_C = SE3d::exp(scale * delta) * T_W_C;
    tau = std::max(space_.inlier_distance_m, tau * kTruncationShrink);
  }
  return T_W_C;
}

std::span<const PlaceHypothesis> GlobalPlaceSearch::search(std::span<const Eigen::Vector3d> points_C,
                                                           const Eigen::Vector3d& up_C) {
  const int n = std::min(static_cast<int>(points_C.size()), max_points_);
  if (n < 3 || !(up_C.norm() > 0.0)) return {};
  points_C = points_C.first(n);
  // Spread the coarse points evenly over the frame.
  const int coarse = std::min(n, options_.coarse_points);
  for (int i = 0; i < coarse; ++i) coarse_C_[i] = points_C[static_cast<std::size_t>(i) * n / coarse];

  const double tau = space_.position_step_m;
  const double tau2 = tau * tau;
  int kept = 0;
  const Eigen::Quaterniond q_tilt = Eigen::Quaterniond::FromTwoVectors(up_C.normalized(), space_.up_W);
  for (int k = 0; k < yaws_; ++k) {
    const Eigen::Quaterniond q_W_C = (Eigen::AngleAxisd(k * space_.yaw_step_rad, space_.up_W) * q_tilt).normalized();
    const Eigen::Matrix3d R = q_W_C.toRotationMatrix();
    for (int i = 0; i < coarse; ++i) rotated_[i] = R * coarse_C_[i];
    for (const Eigen::Vector3d& position : positions_W_) {
      // A pose enters when its summed cost stays below the worst kept one's.
      const double limit = kept == options_.refined_poses ? best_[kept - 1].cost * coarse : coarse;
      double sum = 0.0;
      for (int i = 0; i < coarse && sum < limit; ++i) {
        const double d = field_.distance(rotated_[i] + position);
        sum += std::min(d * d, tau2) / tau2;
      }
      if (sum >= limit) continue;
      int at = std::min(kept, options_.refined_poses - 1);
      while (at > 0 && best_[at - 1].cost > sum / coarse) {
        best_[at] = best_[at - 1];
        --at;
      }
      best_[at] = {SE3d(q_W_C, position), sum / coarse};
      kept = std::min(kept + 1, options_.refined_poses);
    }
  }

  for (int i = 0; i < kept; ++i) refined_[i] = evaluate(points_C, refine(points_C, best_[i].T_W_C));
  std::sort(refined_.begin(), refined_.begin() + kept,
            [](const PlaceHypothesis& a, const PlaceHypothesis& b) { return a.cost < b.cost; });
  int distinct = 0;
  for (int i = 0; i < kept && distinct < options_.hypotheses; ++i) {
    bool seen = false;
    for (int j = 0; j < distinct && !seen; ++j) seen = samePlace(refined_[i].T_W_C, hypotheses_[j].T_W_C);
    if (!seen) hypotheses_[distinct++] = refined_[i];
  }
  return {hypotheses_.data(), static_cast<std::size_t>(distinct)};
}

}  // namespace vifusion::loop
