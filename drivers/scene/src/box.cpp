#include "vifusion/scene/box.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace vifusion::scene {

Box::Box(const BoxSpec& spec) : spec_(spec), cos_yaw_(std::cos(spec.yaw_rad)), sin_yaw_(std::sin(spec.yaw_rad)) {
  if (!(spec.half_extent_m.array() > 0.0).all()) {
    throw std::invalid_argument("scene box '" + std::string(spec.name) + "': half extents must all be > 0");
  }
  if (spec.yaw_rad == 0.0) {
    cos_yaw_ = 1.0;  // exact, so axis-aligned boxes stay exactly axis-aligned
    sin_yaw_ = 0.0;
  }
  const Eigen::Vector3d& h = spec.half_extent_m;
  const Eigen::Vector3d reach_W(std::abs(cos_yaw_) * h.x() + std::abs(sin_yaw_) * h.z(), h.y(),
                                std::abs(sin_yaw_) * h.x() + std::abs(cos_yaw_) * h.z());
  world_bounds_ = Eigen::AlignedBox3d(spec.center_W - reach_W, spec.center_W + reach_W);
}

// R = R_y(yaw) maps box to world: x_B ↦ (cos, 0, −sin), z_B ↦ (sin, 0, cos).
Eigen::Vector3d Box::rotateToWorld(const Eigen::Vector3d& v_B) const {
  return {cos_yaw_ * v_B.x() + sin_yaw_ * v_B.z(), v_B.y(), -sin_yaw_ * v_B.x() + cos_yaw_ * v_B.z()};
}

Eigen::Vector3d Box::rotateToBox(const Eigen::Vector3d& v_W) const {
  return {cos_yaw_ * v_W.x() - sin_yaw_ * v_W.z(), v_W.y(), sin_yaw_ * v_W.x() + cos_yaw_ * v_W.z()};
}

Eigen::Vector3d Box::toBox(const Eigen::Vector3d& p_W) const { return rotateToBox(p_W - spec_.center_W); }

bool Box::intersect(const Eigen::Vector3d& origin_W, const Eigen::Vector3d& direction_W, double t_min,
                    SurfaceHit* hit) const {
  const Eigen::Vector3d o = toBox(origin_W);
  const Eigen::Vector3d d = rotateToBox(direction_W);
  const Eigen::Vector3d& h = spec_.half_extent_m;
  double t_enter = -std::numeric_limits<double>::infinity();
  double t_exit = std::numeric_limits<double>::infinity();
  int enter_axis = -1;
  int exit_axis = -1;
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0.0) {
      // Parallel to this slab: inside it for all t or never.
      if (std::abs(o[i]) > h[i]) return false;
      continue;
    }
    const double t_low = (-h[i] - o[i]) / d[i];
    const double t_high = (h[i] - o[i]) / d[i];
    const double t_near = std::min(t_low, t_high);
    const double t_far = std::max(t_low, t_high);
    if (t_near > t_enter) {
      t_enter = t_near;
      enter_axis = i;
    }
    if (t_far < t_exit) {
      t_exit = t_far;
      exit_axis = i;
    }
  }
  if (t_enter > t_exit) return false;
  // From outside the first crossing is the entry; from inside (t_enter ≤ t_min) it is the exit.
  const bool from_inside = t_enter <= t_min;
  const double t = from_inside ? t_exit : t_enter;
  const int axis = from_inside ? exit_axis : enter_axis;
  if (t <= t_min || t >= hit->t || axis < 0) return false;

  // Both entry and exit faces face the origin when the normal opposes the direction along the axis.
  Eigen::Vector3d n_B = Eigen::Vector3d::Zero();
  n_B[axis] = d[axis] > 0.0 ? -1.0 : 1.0;
  const int side = (d[axis] > 0.0) != from_inside ? 0 : 1;
  // In-face coordinates from the minimum corner; t is the vertical (box y) wherever the face allows.
  const Eigen::Vector3d p_corner = o + t * d + h;
  static constexpr int kS[3] = {2, 0, 0};
  static constexpr int kT[3] = {1, 2, 1};
  hit->t = t;
  hit->normal_W = rotateToWorld(n_B);
  hit->st_m = {p_corner[kS[axis]], p_corner[kT[axis]]};
  hit->s_axis_W = rotateToWorld(Eigen::Vector3d::Unit(kS[axis]));
  hit->t_axis_W = rotateToWorld(Eigen::Vector3d::Unit(kT[axis]));
  hit->box = this;
  hit->axis = axis;
  hit->side = side;
  hit->material = spec_.material;
  hit->variant = spec_.variant;
  return true;
}

double Box::distanceToSurface(const Eigen::Vector3d& p_W) const {
  const Eigen::Vector3d q = toBox(p_W).cwiseAbs() - spec_.half_extent_m;
  const double largest = q.maxCoeff();
  if (largest <= 0.0) return -largest;  // inside: the nearest face
  return q.cwiseMax(0.0).norm();
}

}  // namespace vifusion::scene
