#include "vifusion/scene/living_room.hpp"

#include <algorithm>
#include <limits>

namespace vifusion::scene {
namespace {

constexpr int kLeafSize = 2;  // never split below this: a slab test per box costs about one per node

Box makeShell() {
  const Eigen::AlignedBox3d room = LivingRoom::interior();
  return Box(BoxSpec{.name = "room",
                     .center_W = room.center(),
                     .half_extent_m = 0.5 * room.sizes(),
                     .yaw_rad = 0.0,
                     .material = Material::kWhiteWall,
                     .variant = 0});
}

/// Entry parameter of the ray into axis-aligned bounds (with precomputed inverse direction), or
/// +∞ when it misses them or enters only at or beyond t_best.
double entryInto(const Eigen::AlignedBox3d& bounds, const Eigen::Vector3d& origin,
                 const Eigen::Vector3d& inverse_direction, double t_best) {
  // Scalar on purpose: this is the innermost loop of the renderer, and the plain min/max chain
  // compiles to a handful of SSE2 instructions where the Eigen array form did not inline.
  const double tx0 = (bounds.min().x() - origin.x()) * inverse_direction.x();
  const double tx1 = (bounds.max().x() - origin.x()) * inverse_direction.x();
  const double ty0 = (bounds.min().y() - origin.y()) * inverse_direction.y();
  const double ty1 = (bounds.max().y() - origin.y()) * inverse_direction.y();
  const double tz0 = (bounds.min().z() - origin.z()) * inverse_direction.z();
  const double tz1 = (bounds.max().z() - origin.z()) * inverse_direction.z();
  const double t_near = std::max(std::max(std::min(tx0, tx1), std::min(ty0, ty1)), std::min(tz0, tz1));
  const double t_far = std::min(std::min(std::max(tx0, tx1), std::max(ty0, ty1)), std::max(tz0, tz1));
  return (t_near <= t_far && t_far > 0.0 && t_near < t_best) ? t_near : std::numeric_limits<double>::infinity();
}

double surfaceArea(const Eigen::AlignedBox3d& bounds) {
  if (bounds.isEmpty()) return 0.0;
  const Eigen::Vector3d size = bounds.sizes();
  return 2.0 * (size.x() * size.y() + size.y() * size.z() + size.z() * size.x());
}

}  // namespace

LivingRoom::LivingRoom() : LivingRoom(livingRoomFurniture()) {}

LivingRoom::LivingRoom(const std::vector<BoxSpec>& furniture)
    : shell_(makeShell()), wall_materials_{Material::kWallPanels,  Material::kWhiteWall,     // x = −1.65, x = 3.85
                                           Material::kFloorPlanks, Material::kCeiling,       // floor, ceiling
                                           Material::kWallStripes, Material::kWallBricks} {  // z = −3.2, z = 2.8
  boxes_.reserve(furniture.size());
  for (const BoxSpec& spec : furniture) boxes_.emplace_back(spec);
  nodes_.reserve(2 * boxes_.size() + 1);
  if (!boxes_.empty()) buildBvh(0, static_cast<int>(boxes_.size()), 0);
}

Eigen::AlignedBox3d LivingRoom::cameraRegion() {
  return Eigen::AlignedBox3d(Eigen::Vector3d(-0.1, 0.5, -1.9), Eigen::Vector3d(2.3, 1.8, 1.6));
}

Eigen::AlignedBox3d LivingRoom::interior() {
  return Eigen::AlignedBox3d(Eigen::Vector3d(kMinX_m, kFloorY_m, kMinZ_m),
                             Eigen::Vector3d(kMaxX_m, kCeilingY_m, kMaxZ_m));
}

int LivingRoom::buildBvh(int begin, int end, int depth) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Eigen::AlignedBox3d bounds;  // empty
  for (int i = begin; i < end; ++i) bounds.extend(boxes_[static_cast<std::size_t>(i)].worldBounds());
  nodes_[static_cast<std::size_t>(index)].bounds = bounds;

  // Surface-area heuristic over every split of the centre-sorted boxes on each axis: the expected
  // number of box tests of a random ray is proportional to Σ area(child)·count(child). The scene has
  // ~100 boxes, so the exhaustive O(n² log n) search costs nothing at start-up.
  const auto by_centre = [](int axis) {
    return
        [axis](const Box& a, const Box& b) { return a.worldBounds().center()[axis] < b.worldBounds().center()[axis]; };
  };
  const int count = end - begin;
  double best_cost = surfaceArea(bounds) * count;  // cost of keeping a leaf
  int best_axis = -1;
  int best_split = 0;
  std::vector<double> left_area(static_cast<std::size_t>(count));
  for (int axis = 0; axis < 3 && count > kLeafSize; ++axis) {
    std::sort(boxes_.begin() + begin, boxes_.begin() + end, by_centre(axis));
    Eigen::AlignedBox3d left;
    for (int i = 0; i < count; ++i) {
      left.extend(boxes_[static_cast<std::size_t>(begin + i)].worldBounds());
      left_area[static_cast<std::size_t>(i)] = surfaceArea(left);
    }
    Eigen::AlignedBox3d right;
    for (int i = count - 1; i > 0; --i) {
      right.extend(boxes_[static_cast<std::size_t>(begin + i)].worldBounds());
      const double cost = left_area[static_cast<std::size_t>(i - 1)] * i + surfaceArea(right) * (count - i);
      if (cost < best_cost) {
        best_cost = cost;
        best_axis = axis;
        best_split = begin + i;
      }
    }
  }
  if (best_axis < 0 || depth + 1 >= kMaxBvhDepth) {
    nodes_[static_cast<std::size_t>(index)].first = begin;
    nodes_[static_cast<std::size_t>(index)].count = count;
    return index;
  }
  std::sort(boxes_.begin() + begin, boxes_.begin() + end, by_centre(best_axis));
  buildBvh(begin, best_split, depth + 1);  // lands at index + 1
  const int right = buildBvh(best_split, end, depth + 1);
  nodes_[static_cast<std::size_t>(index)].first = right;
  return index;
}

bool LivingRoom::intersect(const Eigen::Vector3d& origin_W, const Eigen::Vector3d& direction_W, SurfaceHit* hit) const {
  SurfaceHit best;
  bool found = shell_.intersect(origin_W, direction_W, 0.0, &best);
  if (found) best.material = wall_materials_[static_cast<std::size_t>(2 * best.axis + best.side)];
  if (!nodes_.empty()) {
    // A huge finite stand-in for 1/0 keeps (bound − origin)·inverse free of 0·∞ = NaN for rays
    // parallel to a slab, which would otherwise drop boxes the ray touches.
    const Eigen::Vector3d inverse = direction_W.unaryExpr([](double d) { return d != 0.0 ? 1.0 / d : 1e300; });
    // Front-to-back: the nearer child is visited first, so the farther one is usually culled by the
    // hit found in the nearer one.
    struct Pending {
      int index;
      double t_entry;
    };
    Pending stack[kMaxBvhDepth + 1];
    int top = 0;
    const double t_root = entryInto(nodes_[0].bounds, origin_W, inverse, best.t);
    if (t_root < best.t) stack[top++] = {0, t_root};
    while (top > 0) {
      const Pending pending = stack[--top];
      if (pending.t_entry >= best.t) continue;  // a hit found since it was pushed is nearer
      const int index = pending.index;
      const BvhNode& node = nodes_[static_cast<std::size_t>(index)];
      if (node.count > 0) {
        for (int i = node.first; i < node.first + node.count; ++i) {
          found |= boxes_[static_cast<std::size_t>(i)].intersect(origin_W, direction_W, 0.0, &best);
        }
        continue;
      }
      const int near_child = index + 1;
      const int far_child = node.first;
      double t_near = entryInto(nodes_[static_cast<std::size_t>(near_child)].bounds, origin_W, inverse, best.t);
      double t_far = entryInto(nodes_[static_cast<std::size_t>(far_child)].bounds, origin_W, inverse, best.t);
      int first = near_child;
      int second = far_child;
      if (t_far < t_near) {
        std::swap(first, second);
        std::swap(t_near, t_far);
      }
      if (t_far < best.t) stack[top++] = {second, t_far};
      if (t_near < best.t) stack[top++] = {first, t_near};
    }
  }
  if (found) *hit = best;
  return found;
}

bool LivingRoom::intersectAmong(const Eigen::Vector3d& origin_W, const Eigen::Vector3d& direction_W,
                                std::span<const Box* const> boxes, SurfaceHit* hit) const {
  SurfaceHit best;
  bool found = false;
  for (const Box* box : boxes) found |= box->intersect(origin_W, direction_W, 0.0, &best);
  if (!found) return false;
  if (best.box == &shell_) best.material = wall_materials_[static_cast<std::size_t>(2 * best.axis + best.side)];
  *hit = best;
  return true;
}

double LivingRoom::distanceToSurface(const Eigen::Vector3d& p_W) const {
  double best = shell_.distanceToSurface(p_W);
  if (nodes_.empty()) return best;
  int stack[kMaxBvhDepth + 1];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const int index = stack[--top];
    const BvhNode& node = nodes_[static_cast<std::size_t>(index)];
    // The distance to the solid bounds is a lower bound on the distance to any surface inside them.
    if (node.bounds.exteriorDistance(p_W) >= best) continue;
    if (node.count > 0) {
      for (int i = node.first; i < node.first + node.count; ++i) {
        best = std::min(best, boxes_[static_cast<std::size_t>(i)].distanceToSurface(p_W));
      }
    } else {
      stack[top++] = node.first;
      stack[top++] = index + 1;
    }
  }
  return best;
}

}  // namespace vifusion::scene
