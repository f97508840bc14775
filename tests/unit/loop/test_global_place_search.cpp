// loop/surface_distance_field.hpp and loop/global_place_search.hpp in a synthetic room: a box-shaped room with a
// cupboard in one corner, its surfaces sampled every 2 cm, seen by an 80×60 block camera from a known pose. The
// field's distances against the exact ones, its gradient and the search's point Jacobian against numeric
// differences, the search finding the camera from anywhere in the room, the symmetric room (no cupboard) giving
// its twin poses as equal hypotheses, and no allocation in search().

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "vifusion/core/error.hpp"
#include "vifusion/loop/global_place_search.hpp"
#include "vifusion/loop/surface_distance_field.hpp"
#include "vifusion/test/counting_allocations.hpp"

namespace vifusion::loop {
namespace {

constexpr double kSurfaceSpacing_m = 0.02;
constexpr int kFactor = 4;                                                       // 320×240 camera, 80×60 blocks
const Eigen::Vector3d kRoomMin(0.0, 0.0, 0.0), kRoomMax(5.0, 3.0, 4.0);          // W: y up
const Eigen::Vector3d kCupboardMin(3.8, 0.0, 0.0), kCupboardMax(5.0, 1.8, 0.6);  // against two walls

PinholeCamera camera() { return PinholeCamera::create(320, 240, 250.0, 250.0, 159.5, 119.5); }

/// Points every kSurfaceSpacing_m on the faces of the box [lo, hi].
void sampleBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, std::vector<Eigen::Vector3f>& out) {
  for (int axis = 0; axis < 3; ++axis) {
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    for (const double side : {lo[axis], hi[axis]}) {
      for (double s = lo[a]; s <= hi[a] + 1e-9; s += kSurfaceSpacing_m) {
        for (double t = lo[b]; t <= hi[b] + 1e-9; t += kSurfaceSpacing_m) {
          Eigen::Vector3d p;
          p[axis] = side;
          p[a] = s;
          p[b] = t;
          out.push_back(p.cast<float>());
        }
      }
    }
  }
}

std::vector<Eigen::Vector3f> roomPoints(bool cupboard) {
  std::vector<Eigen::Vector3f> points;
  sampleBox(kRoomMin, kRoomMax, points);
  if (cupboard) sampleBox(kCupboardMin, kCupboardMax, points);
  return points;
}

/// Ray parameter where a ray from inside the room leaves it, and where it enters the cupboard (infinity: misses).
double exitRoom(const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  double t = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) {
    if (d[i] > 0) t = std::min(t, (kRoomMax[i] - o[i]) / d[i]);
    if (d[i] < 0) t = std::min(t, (kRoomMin[i] - o[i]) / d[i]);
  }
  return t;
}
double enterBox(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& lo,
                const Eigen::Vector3d& hi) {
  double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) {
    const double a = (lo[i] - o[i]) / d[i], b = (hi[i] - o[i]) / d[i];
    t0 = std::max(t0, std::min(a, b));
    t1 = std::min(t1, std::max(a, b));
  }
  return t0 <= t1 ? t0 : std::numeric_limits<double>::infinity();
}

/// The block image's depths of the room seen from T_W_C (colour unused by the search).
FernImage renderRoom(const SE3d& T_W_C, bool cupboard) {
  const PinholeCamera cam = camera();
  FernImage image(cam.width / kFactor, cam.height / kFactor);
  const double half_block = 0.5 * (kFactor - 1);
  for (int v = 0; v < image.height(); ++v) {
    for (int u = 0; u < image.width(); ++u) {
      const Eigen::Vector3d ray_C = cam.backProject({u * kFactor + half_block, v * kFactor + half_block}, 1.0);
      const Eigen::Vector3d d_W = T_W_C.rotationMatrix() * ray_C;
      double t = exitRoom(T_W_C.translation(), d_W);
      if (cupboard) t = std::min(t, enterBox(T_W_C.translation(), d_W, kCupboardMin, kCupboardMax));
      image.depth_m(u, v) = t <= 4.0 ? static_cast<float>(t) : 0.0f;  // t is the depth: ray_C.z() = 1
    }
  }
  return image;
}

/// A camera at `p_W` looking at `target_W`, upright (its x axis horizontal; camera y points down, z forward).
SE3d cameraLookingAt(const Eigen::Vector3d& p_W, const Eigen::Vector3d& target_W) {
  const Eigen::Vector3d z = (target_W - p_W).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitY()).normalized();
  Eigen::Matrix3d R_W_C;
  R_W_C << x, z.cross(x), z;
  return SE3d(Eigen::Quaterniond(R_W_C), p_W);
}

SearchSpace roomSpace() {
  SearchSpace space;
  space.up_W = Eigen::Vector3d::UnitY();
  space.min_height_m = 1.0;
  space.max_height_m = 1.6;
  return space;  // steps, clearance and inlier distance at their defaults (the tracker's bounds)
}

double angleDeg(const SE3d& a, const SE3d& b) {
  return Eigen::AngleAxisd((a.inverse() * b).quaternion()).angle() * 180.0 / std::numbers::pi;
}

TEST(SurfaceDistanceField, DistancesToAPlaneWithinItsQuantisation) {
  std::vector<Eigen::Vector3f> floor;
  sampleBox({0.0, 0.0, 0.0}, {2.0, 0.0, 2.0}, floor);
  const SurfaceDistanceField field(floor, {});
  const double quantisation = std::sqrt(3.0) / 2.0 * field.voxelSize();
  for (const double height : {0.0, 0.03, 0.1, 0.27, 0.45}) {
    EXPECT_NEAR(field.distance({1.0, height, 1.0}), height, quantisation) << height;
    EXPECT_NEAR(field.distance({0.5, -height, 1.3}), height, quantisation) << height;
  }
  // Beside the floor's edge the nearest point is the edge.
  EXPECT_NEAR(field.distance({2.3, 0.4, 1.0}), 0.5, quantisation);
  EXPECT_EQ(field.distance({1.0, 5.0, 1.0}), std::numeric_limits<double>::infinity());  // off the grid
}

TEST(SurfaceDistanceField, GradientMatchesNumericDifferences) {
  const SurfaceDistanceField field(roomPoints(true), {});
  const double h = 1e-6;
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(1.013, 1.21, 0.337), Eigen::Vector3d(3.61, 1.92, 0.71),
                                   Eigen::Vector3d(0.2213, 2.8731, 3.612)}) {
    Eigen::Vector3d gradient;
    field.distance(p, &gradient);
    for (int i = 0; i < 3; ++i) {
      const double numeric =
          (field.distance(p + h * Eigen::Vector3d::Unit(i)) - field.distance(p - h * Eigen::Vector3d::Unit(i))) /
          (2 * h);
      EXPECT_NEAR(gradient[i], numeric, 1e-6) << i;
    }
  }
}

TEST(SurfaceDistanceField, CoarsensToItsVoxelBudgetAndRefusesNoPoints) {
  DistanceFieldOptions options;
  options.max_voxels = 20'000;
  const SurfaceDistanceField field(roomPoints(false), options);
  EXPECT_LE(std::int64_t{field.dimensions().prod()}, options.max_voxels);
  EXPECT_GT(field.voxelSize(), 0.05);
  EXPECT_NEAR(field.distance({2.5, 1.5, 2.0}), 1.5, std::sqrt(3.0) / 2.0 * field.voxelSize());
  const std::vector<Eigen::Vector3f> none = {Eigen::Vector3f::Constant(std::nanf(""))};
  EXPECT_THROW(SurfaceDistanceField(none, {}), Error);
  options.voxel_size_m = 0.0;
  EXPECT_THROW(SurfaceDistanceField(roomPoints(false), options), Error);
}

TEST(GlobalPlaceSearch, PointJacobianMatchesNumericDifferences) {
  const SurfaceDistanceField field(roomPoints(true), {});
  const SE3d T_W_C = cameraLookingAt({2.1, 1.3, 1.7}, {4.0, 0.5, 0.4});
  const double h = 1e-6;
  for (const Eigen::Vector3d& p_C : {Eigen::Vector3d(0.3, -0.2, 2.1), Eigen::Vector3d(-0.7, 0.4, 1.33)}) {
    Eigen::Matrix<double, 1, 6> J;
    fieldResidual(field, T_W_C, p_C, &J);
    for (int i = 0; i < 6; ++i) {
      const Vector6d delta = h * Vector6d::Unit(i);
      const double numeric =
          (fieldResidual(field, SE3d::exp(delta) * T_W_C, p_C) - fieldResidual(field, SE3d::exp(-delta) * T_W_C, p_C)) /
          (2 * h);
      EXPECT_NEAR(J(i), numeric, 1e-5) << i;
    }
  }
}

TEST(GlobalPlaceSearch, FindsTheCameraAnywhereInTheRoom) {
  GlobalPlaceSearch search(SurfaceDistanceField(roomPoints(true), {}), roomSpace(), {}, 80 * 60);
  std::vector<Eigen::Vector3d> points(80 * 60);
  // Views across the room that include the cupboard (a view of a bare corner is as ambiguous as the room's
  // half-turn symmetry makes it: the next test).
  for (const SE3d& truth :
       {cameraLookingAt({1.23, 1.31, 1.07}, {4.4, 0.5, 0.5}), cameraLookingAt({3.0, 1.45, 3.2}, {4.5, 0.8, 0.3}),
        cameraLookingAt({1.2, 1.12, 3.0}, {4.0, 0.6, 0.6})}) {
    const int n = blockPoints(renderRoom(truth, true), camera(), kFactor, points);
    ASSERT_GT(n, 1000);
    const Eigen::Vector3d up_C = truth.inverse().rotationMatrix() * Eigen::Vector3d::UnitY();
    const std::span<const PlaceHypothesis> found = search.search(std::span(points).first(n), up_C);
    ASSERT_FALSE(found.empty());
    const PlaceHypothesis& best = found.front();
    EXPECT_LT((best.T_W_C.translation() - truth.translation()).norm(), 0.03) << truth.translation().transpose();
    EXPECT_LT(angleDeg(best.T_W_C, truth), 1.0) << truth.translation().transpose();
    EXPECT_GT(best.inlier_share, 0.95);
    // The others are other places, scored worse.
    for (std::size_t i = 1; i < found.size(); ++i) EXPECT_GT(found[i].cost, best.cost);
  }
}

TEST(GlobalPlaceSearch, ASymmetricRoomGivesItsTwinPosesAsEqualHypotheses) {
  // Without the cupboard the room is symmetric under a half turn about its vertical centre line: the camera and
  // its twin explain the frame equally, and the search says so rather than choosing.
  GlobalPlaceSearch search(SurfaceDistanceField(roomPoints(false), {}), roomSpace(), {}, 80 * 60);
  std::vector<Eigen::Vector3d> points(80 * 60);
  const SE3d truth = cameraLookingAt({1.23, 1.31, 1.07}, {4.4, 0.5, 0.5});
  const SE3d half_turn(Eigen::Quaterniond(Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitY())),
                       Eigen::Vector3d(5.0, 0.0, 4.0));
  const SE3d twin = half_turn * truth;
  const int n = blockPoints(renderRoom(truth, false), camera(), kFactor, points);
  const std::span<const PlaceHypothesis> found =
      search.search(std::span(points).first(n), truth.inverse().rotationMatrix() * Eigen::Vector3d::UnitY());
  ASSERT_GE(found.size(), 2u);
  bool truth_found = false, twin_found = false;
  for (const PlaceHypothesis& hypothesis : found) {
    if (hypothesis.cost > found.front().cost + 0.01) continue;  // only the equally good ones
    truth_found |= (hypothesis.T_W_C.translation() - truth.translation()).norm() < 0.03;
    twin_found |= (hypothesis.T_W_C.translation() - twin.translation()).norm() < 0.03;
  }
  EXPECT_TRUE(truth_found);
  EXPECT_TRUE(twin_found);
}

TEST(GlobalPlaceSearch, SearchAllocatesNothing) {
  GlobalPlaceSearch search(SurfaceDistanceField(roomPoints(true), {}), roomSpace(), {}, 80 * 60);
  std::vector<Eigen::Vector3d> points(80 * 60);
  const SE3d truth = cameraLookingAt({2.0, 1.3, 2.0}, {4.4, 0.5, 0.5});
  const int n = blockPoints(renderRoom(truth, true), camera(), kFactor, points);
  const Eigen::Vector3d up_C = truth.inverse().rotationMatrix() * Eigen::Vector3d::UnitY();
  const std::uint64_t before = test::heapAllocationCount();
  const std::size_t found = search.search(std::span(points).first(n), up_C).size();
  EXPECT_EQ(test::heapAllocationCount(), before);
  EXPECT_GT(found, 0u);
}

TEST(GlobalPlaceSearch, RefusesOptionsOutOfRange) {
  SearchSpace space = roomSpace();
  space.yaw_step_rad = 0.0;
  EXPECT_THROW(GlobalPlaceSearch(SurfaceDistanceField(roomPoints(false), {}), space, {}, 100), Error);
  GlobalSearchOptions options;
  options.refined_poses = options.hypotheses - 1;
  EXPECT_THROW(GlobalPlaceSearch(SurfaceDistanceField(roomPoints(false), {}), roomSpace(), options, 100), Error);
  space = roomSpace();
  space.min_height_m = 10.0;  // above the room: no position clear of the map within the grid
  space.max_height_m = 11.0;
  EXPECT_THROW(GlobalPlaceSearch(SurfaceDistanceField(roomPoints(false), {}), space, {}, 100), Error);
}

}  // namespace
}  // namespace vifusion::loop
