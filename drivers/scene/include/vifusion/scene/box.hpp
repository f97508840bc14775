#pragma once
// The one geometric primitive of the synthetic scene: a box, axis-aligned or turned about the world
// up axis (yaw). The room itself is a box seen from inside, so one slab routine serves walls and
// furniture: it returns the first crossing of the box surface ahead of the ray origin, which is the
// entry face from outside and the exit face (a wall) from inside.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <limits>
#include <string_view>

#include "vifusion/scene/texture.hpp"

namespace vifusion::scene {

class Box;

/// Where a ray meets a surface.
struct SurfaceHit {
  double t = std::numeric_limits<double>::infinity();  ///< ray parameter: hit point = origin + t·direction
  Eigen::Vector3d normal_W = Eigen::Vector3d::Zero();  ///< unit normal on the side the ray came from
  Eigen::Vector2d st_m = Eigen::Vector2d::Zero();      ///< texture coordinates in the face [m] (texture.hpp)
  Eigen::Vector3d s_axis_W = Eigen::Vector3d::Zero();  ///< unit direction in which s grows: ∂s/∂p_W [m/m]
  Eigen::Vector3d t_axis_W = Eigen::Vector3d::Zero();  ///< unit direction in which t grows: ∂t/∂p_W [m/m]
  const Box* box = nullptr;                            ///< the box hit; with axis and side, names the face
  int axis = 0;                                        ///< box axis the face is normal to (0 x, 1 y, 2 z)
  int side = 0;                                        ///< 0 at −half extent, 1 at +half extent
  Material material = Material::kWhiteWall;
  std::uint32_t variant = 0;
};

/// True when both hits lie on the same face of the same box, so that texture coordinates and shading
/// continue smoothly from one to the other.
inline bool sameFace(const SurfaceHit& a, const SurfaceHit& b) {
  return a.box == b.box && a.axis == b.axis && a.side == b.side;
}

/// What a box is: placement, size and surface.
struct BoxSpec {
  std::string_view name;                                    ///< for tests and debugging, e.g. "sofa_back"
  Eigen::Vector3d center_W = Eigen::Vector3d::Zero();       ///< [m]
  Eigen::Vector3d half_extent_m = Eigen::Vector3d::Zero();  ///< along the box's own axes [m], all > 0
  double yaw_rad = 0.0;  ///< rotation about world +y: box x axis = (cos, 0, −sin) in the world
  Material material = Material::kWood;
  std::uint32_t variant = 0;
};

class Box {
 public:
  explicit Box(const BoxSpec& spec);

  const BoxSpec& spec() const { return spec_; }
  /// World-axis-aligned bounds (of the turned box, if it is yawed) [m].
  const Eigen::AlignedBox3d& worldBounds() const { return world_bounds_; }

  /// First crossing of the box surface with t_min < t < hit->t, written to *hit (material and variant
  /// from the spec). direction_W need not be unit length. Returns false, leaving *hit alone, otherwise.
  bool intersect(const Eigen::Vector3d& origin_W, const Eigen::Vector3d& direction_W, double t_min,
                 SurfaceHit* hit) const;

  /// Unsigned distance from p_W to the box's surface (not to the solid) [m]: inside points measure to
  /// the nearest face too, which is what the room's walls need.
  double distanceToSurface(const Eigen::Vector3d& p_W) const;

  /// p_W in the box frame (origin at the centre, axes of the box) [m].
  Eigen::Vector3d toBox(const Eigen::Vector3d& p_W) const;
  /// A direction in the box frame.
  Eigen::Vector3d rotateToBox(const Eigen::Vector3d& v_W) const;
  /// A box-frame direction in the world.
  Eigen::Vector3d rotateToWorld(const Eigen::Vector3d& v_B) const;

 private:
  BoxSpec spec_;
  double cos_yaw_ = 1.0;
  double sin_yaw_ = 0.0;
  Eigen::AlignedBox3d world_bounds_;
};

}  // namespace vifusion::scene
