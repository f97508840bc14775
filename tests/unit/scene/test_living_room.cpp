#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "vifusion/scene/counter_rng.hpp"
#include "vifusion/scene/living_room.hpp"

namespace vifusion::scene {
namespace {

const LivingRoom& room() {
  static const LivingRoom instance;
  return instance;
}

const Box& furniture(std::string_view name) {
  for (const Box& box : room().furniture()) {
    if (box.spec().name == name) return box;
  }
  throw std::runtime_error("no furniture named " + std::string(name));
}

/// Deterministic uniform in [lo, hi].
double uniform(double lo, double hi, std::uint64_t i, std::uint64_t salt) {
  return lo + (hi - lo) * static_cast<double>(counterBits(7, salt, i) >> 11) * 0x1.0p-53;
}

TEST(LivingRoom, RoomHasTheDocumentedSize) {
  const Eigen::AlignedBox3d inside = LivingRoom::interior();
  EXPECT_NEAR(inside.sizes().x(), 5.5, 1e-12);
  EXPECT_NEAR(inside.sizes().y(), 2.7, 1e-12);
  EXPECT_NEAR(inside.sizes().z(), 6.0, 1e-12);
  EXPECT_NEAR(inside.center().x(), 1.1, 1e-12);
  EXPECT_NEAR(inside.center().z(), -0.2, 1e-12);
  EXPECT_GT(room().furniture().size(), 50U);
}

TEST(LivingRoom, FurnitureKeepsClearOfEveryCameraPathAndInsideTheRoom) {
  const Eigen::AlignedBox3d keep_out(
      LivingRoom::cameraRegion().min() - Eigen::Vector3d::Constant(LivingRoom::kFurnitureClearance_m),
      LivingRoom::cameraRegion().max() + Eigen::Vector3d::Constant(LivingRoom::kFurnitureClearance_m));
  const Eigen::AlignedBox3d inside = LivingRoom::interior();
  for (const Box& box : room().furniture()) {
    // Yawed boxes are tested through their world bounds, which is conservative.
    EXPECT_TRUE(keep_out.intersection(box.worldBounds()).isEmpty()) << box.spec().name;
    EXPECT_TRUE(inside.contains(box.worldBounds().min()) && inside.contains(box.worldBounds().max()))
        << box.spec().name;
  }
}

TEST(LivingRoom, DistanceAtTheRoomCentreIsTheCeiling) {
  // Above the coffee table (top 0.26 m): the ceiling at 2.7 m is the nearest surface.
  EXPECT_NEAR(room().distanceToSurface(Eigen::Vector3d(1.1, 1.6, -0.2)), 1.1, 1e-12);
  // Lower, above a part of the coffee table away from the book on it, the table top is nearest.
  const Box& table = furniture("table_top");
  const double table_top_m = table.spec().center_W.y() + table.spec().half_extent_m.y();
  Eigen::Vector3d p_W = table.spec().center_W + table.rotateToWorld(Eigen::Vector3d(-0.35, 0.0, -0.2));
  p_W.y() = 1.2;
  EXPECT_NEAR(room().distanceToSurface(p_W), 1.2 - table_top_m, 1e-12);
}

TEST(LivingRoom, DistanceNearAFaceIsTheOffset) {
  // 2 cm in front of the middle of the sofa back's room-facing (+x) face, above the cushions.
  const Box& back = furniture("sofa_back");
  const Eigen::Vector3d& c = back.spec().center_W;
  const Eigen::Vector3d& h = back.spec().half_extent_m;
  EXPECT_NEAR(room().distanceToSurface(Eigen::Vector3d(c.x() + h.x() + 0.02, c.y() + 0.1, c.z())), 0.02, 1e-12);
  // Inside the same box, 3 cm below its top face and far from the others: distance to that face.
  EXPECT_NEAR(back.distanceToSurface(Eigen::Vector3d(c.x(), c.y() + h.y() - 0.03, c.z())), 0.03, 1e-12);
}

TEST(LivingRoom, DistanceNearAYawedFaceIsTheOffset) {
  const Box& base = furniture("armchair_base");
  const Eigen::Vector3d p_W =
      base.spec().center_W + base.rotateToWorld(Eigen::Vector3d(base.spec().half_extent_m.x() + 0.01, 0.0, 0.0));
  EXPECT_NEAR(room().distanceToSurface(p_W), 0.01, 1e-12);
}

TEST(LivingRoom, DistanceOffABoxCornerIsEuclidean) {
  const Box& top = furniture("cabinet_top");
  const Eigen::Vector3d corner = top.worldBounds().max();
  EXPECT_NEAR(room().distanceToSurface(corner + Eigen::Vector3d(0.03, 0.04, 0.12)), 0.13, 1e-12);
}

TEST(LivingRoom, DistanceInARoomCornerIsTheNearestWall) {
  // Upper south-west corner, above the door: 3 cm from the west wall, 4 cm from the ceiling, 5 cm
  // from the south wall.
  const Eigen::Vector3d p(LivingRoom::kMinX_m + 0.03, LivingRoom::kCeilingY_m - 0.04, LivingRoom::kMaxZ_m - 0.05);
  EXPECT_NEAR(room().distanceToSurface(p), 0.03, 1e-12);
  // Outside the room, beyond the white wall.
  EXPECT_NEAR(room().distanceToSurface(Eigen::Vector3d(5.0, 1.0, 0.0)), 5.0 - LivingRoom::kMaxX_m, 1e-12);
}

TEST(LivingRoom, DistanceEqualsBruteForceMinimum) {
  // The BVH only prunes; the answer must be the minimum over every surface.
  const Box shell(BoxSpec{.name = "room",
                          .center_W = LivingRoom::interior().center(),
                          .half_extent_m = 0.5 * LivingRoom::interior().sizes()});
  for (std::uint64_t i = 0; i < 2000; ++i) {
    const Eigen::Vector3d p(uniform(-2.0, 4.2, i, 1), uniform(-0.3, 3.0, i, 2), uniform(-3.5, 3.1, i, 3));
    double expected = shell.distanceToSurface(p);
    for (const Box& box : room().furniture()) expected = std::min(expected, box.distanceToSurface(p));
    ASSERT_NEAR(room().distanceToSurface(p), expected, 1e-15) << p.transpose();
  }
}

TEST(LivingRoom, IntersectEqualsBruteForceNearestHit) {
  for (std::uint64_t i = 0; i < 4000; ++i) {
    const Eigen::Vector3d origin(uniform(-0.1, 2.3, i, 4), uniform(0.5, 1.8, i, 5), uniform(-1.9, 1.6, i, 6));
    const Eigen::Vector3d direction(uniform(-1, 1, i, 7), uniform(-1, 1, i, 8), uniform(-1, 1, i, 9));
    SurfaceHit hit;
    ASSERT_TRUE(room().intersect(origin, direction, &hit));
    double nearest = std::numeric_limits<double>::infinity();
    for (const Box& box : room().furniture()) {
      SurfaceHit candidate;
      if (box.intersect(origin, direction, 0.0, &candidate)) nearest = std::min(nearest, candidate.t);
    }
    if (nearest < hit.t) ADD_FAILURE() << "missed a box at t = " << nearest << ", returned " << hit.t;
    // The hit lies on a surface and its normal faces the ray.
    EXPECT_LT(room().distanceToSurface(origin + hit.t * direction), 1e-12);
    EXPECT_LT(hit.normal_W.dot(direction), 0.0);
    EXPECT_NEAR(hit.normal_W.norm(), 1.0, 1e-12);
  }
}

TEST(LivingRoom, WhiteWallIsTheEastWall) {
  SurfaceHit hit;
  ASSERT_TRUE(room().intersect(Eigen::Vector3d(2.3, 1.35, 0.0), Eigen::Vector3d(1, 0.1, 0.2), &hit));
  EXPECT_EQ(hit.material, Material::kWhiteWall);
  EXPECT_NEAR(hit.normal_W.x(), -1.0, 1e-15);
}

TEST(Box, YawedBoxHitsAndMissesLikeItsRotatedFrame) {
  // A 2 × 1 × 1 box turned 90°: its long side now runs along world z.
  const Box box(BoxSpec{.name = "test",
                        .center_W = Eigen::Vector3d(0, 0, 0),
                        .half_extent_m = Eigen::Vector3d(1.0, 0.5, 0.5),
                        .yaw_rad = std::numbers::pi / 2});
  SurfaceHit hit;
  EXPECT_TRUE(box.intersect(Eigen::Vector3d(0, 0, 5), Eigen::Vector3d(0, 0, -1), 0.0, &hit));
  EXPECT_NEAR(hit.t, 4.0, 1e-12);
  EXPECT_NEAR(hit.normal_W.z(), 1.0, 1e-12);
  SurfaceHit miss;
  EXPECT_FALSE(box.intersect(Eigen::Vector3d(0.8, 0, 5), Eigen::Vector3d(0, 0, -1), 0.0, &miss));
  EXPECT_NEAR(box.worldBounds().max().z(), 1.0, 1e-12);
  EXPECT_NEAR(box.worldBounds().max().x(), 0.5, 1e-12);
}

TEST(Box, FromInsideTheFirstCrossingIsTheExit) {
  const Box box(BoxSpec{.name = "test", .half_extent_m = Eigen::Vector3d(1.0, 1.0, 1.0)});
  SurfaceHit hit;
  ASSERT_TRUE(box.intersect(Eigen::Vector3d(0.5, 0, 0), Eigen::Vector3d(2, 0, 0), 0.0, &hit));
  EXPECT_DOUBLE_EQ(hit.t, 0.25);
  EXPECT_EQ(hit.axis, 0);
  EXPECT_EQ(hit.side, 1);
  EXPECT_EQ(hit.normal_W, Eigen::Vector3d(-1, 0, 0));
}

TEST(Box, RejectsDegenerateExtents) {
  EXPECT_THROW(Box(BoxSpec{.name = "flat", .half_extent_m = Eigen::Vector3d(1.0, 0.0, 1.0)}), std::invalid_argument);
}

}  // namespace
}  // namespace vifusion::scene
