#pragma once
// The procedural living room the simulator renders: a 5.5 m × 6 m × 2.7 m room (world y up, gravity
// −y, floor at y = 0) around the ICL-NUIM camera paths, furnished with boxes. The camera paths stay in
// cameraRegion(); no furniture comes within kFurnitureClearance_m of it (a test checks), so no path
// passes through an object. The x = 3.85 m wall is plain white for the `white_wall` preset.
//
// Geometry is exact: ray hits come from closed-form slab intersections in double precision, and
// distanceToSurface() is the exact distance to the union of all primitive surfaces, the ground truth
// of the reconstruction-error metric (algorithms.md §4.3, but point-to-surface instead of point-to-
// vertex). That union includes faces hidden by contact (a cushion's underside on the sofa base, a
// frame's back on the wall); they coincide with or lie inside visible geometry, so they only matter
// for map points inside furniture, which a reconstruction does not produce.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <span>
#include <vector>

#include "vifusion/scene/box.hpp"

namespace vifusion::scene {

class LivingRoom {
 public:
  static constexpr double kFloorY_m = 0.0;
  static constexpr double kCeilingY_m = 2.7;
  static constexpr double kMinX_m = -1.65;  ///< 5.5 m along x, centred at x = 1.1
  static constexpr double kMaxX_m = 3.85;   ///< the plain white wall
  static constexpr double kMinZ_m = -3.2;   ///< 6 m along z, centred at z = −0.2
  static constexpr double kMaxZ_m = 2.8;
  static constexpr double kFurnitureClearance_m = 0.2;

  /// The standard furnished room.
  LivingRoom();
  /// The same walls with other furniture (tests, other presets). Throws std::invalid_argument for a
  /// degenerate box.
  explicit LivingRoom(const std::vector<BoxSpec>& furniture);

  /// Where the ICL-NUIM camera paths run (data/README.md): x ∈ [−0.1, 2.3], y ∈ [0.5, 1.8],
  /// z ∈ [−1.9, 1.6] m.
  static Eigen::AlignedBox3d cameraRegion();
  /// Interior of the room [m].
  static Eigen::AlignedBox3d interior();

  /// Nearest surface along origin_W + t·direction_W with t > 0 (direction need not be unit length).
  /// From inside the room there is always one; from outside, false when the ray misses the room.
  bool intersect(const Eigen::Vector3d& origin_W, const Eigen::Vector3d& direction_W, SurfaceHit* hit) const;

  /// The same among `boxes` only (this room's furniture or its shell, as SurfaceHit::box names them):
  /// a cheap re-cast of a ray next to rays already cast, whose hits name what can be seen there.
  /// False when none of them is hit.
  bool intersectAmong(const Eigen::Vector3d& origin_W, const Eigen::Vector3d& direction_W,
                      std::span<const Box* const> boxes, SurfaceHit* hit) const;

  /// Unsigned distance from p_W to the nearest scene surface (walls, floor, ceiling, furniture) [m].
  double distanceToSurface(const Eigen::Vector3d& p_W) const;

  /// The furniture boxes, in the order of the BVH leaves (not the order they were given in).
  std::span<const Box> furniture() const { return boxes_; }

 private:
  /// Node of the bounding-volume hierarchy over boxes_: a leaf holds boxes_[first, first + count);
  /// an inner node (count == 0) has its children at this index + 1 and at `first`.
  struct BvhNode {
    Eigen::AlignedBox3d bounds;
    int first = 0;
    int count = 0;
  };
  static constexpr int kMaxBvhDepth = 32;

  int buildBvh(int begin, int end, int depth);

  Box shell_;
  std::array<Material, 6> wall_materials_{};  ///< by 2·axis + side
  std::vector<Box> boxes_;
  std::vector<BvhNode> nodes_;
};

/// The standard furniture: sofa, coffee table on a rug, bookshelf with books, cabinet with a TV,
/// picture frames, a door, an armchair, a floor lamp and a plant.
std::vector<BoxSpec> livingRoomFurniture();

}  // namespace vifusion::scene
