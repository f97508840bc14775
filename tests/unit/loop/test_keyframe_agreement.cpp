// loop/keyframe_agreement.hpp on a rendered wall: a frame placed where it was taken agrees with the keyframe in
// depth and colour; placed 20 cm along the wall (the alignment slid on the plane) it still agrees in depth and no
// longer in colour; a blank wall leaves colour unable to tell.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "vifusion/core/error.hpp"
#include "vifusion/loop/keyframe_agreement.hpp"

namespace vifusion {
namespace {

constexpr int kFactor = 4;
constexpr double kWallZ_m = 2.0;          // the wall: the plane z = 2 m of the world
constexpr double kStripePeriod_m = 0.12;  // its texture: vertical stripes along x
constexpr double kDepthGate_m = 0.10;     // the ICP's association gate

PinholeCamera camera() { return PinholeCamera::create(320, 240, 250.0, 250.0, 159.5, 119.5); }

/// The block image of the wall seen from T_W_C (camera looking along +z of the world at the identity).
loop::FernImage renderWall(const SE3d& T_W_C, bool textured) {
  const PinholeCamera cam = camera();
  loop::FernImage image(cam.width / kFactor, cam.height / kFactor);
  const double half_block = 0.5 * (kFactor - 1);
  for (int v = 0; v < image.height(); ++v) {
    for (int u = 0; u < image.width(); ++u) {
      const Eigen::Vector3d ray_C = cam.backProject({u * kFactor + half_block, v * kFactor + half_block}, 1.0);
      const Eigen::Vector3d ray_W = T_W_C.rotationMatrix() * ray_C;
      const double s = (kWallZ_m - T_W_C.translation().z()) / ray_W.z();
      const Eigen::Vector3d p_W = T_W_C.translation() + s * ray_W;
      image.depth_m(u, v) = static_cast<float>((T_W_C.inverse() * p_W).z());
      const double luma =
          textured ? 128.0 + 90.0 * std::sin(2.0 * std::numbers::pi * p_W.x() / kStripePeriod_m) : 128.0;
      const auto grey = static_cast<std::uint8_t>(std::lround(luma));
      image.rgb(u, v) = {grey, grey, grey};
    }
  }
  return image;
}

loop::FernKeyframe keyframeOf(const loop::FernImage& image, const SE3d& T_W_K) {
  loop::FernKeyframe keyframe;
  keyframe.T_W_C = T_W_K;
  keyframe.rgb = image.rgb.view();
  keyframe.depth_m = image.depth_m.view();
  return keyframe;
}

SE3d pose(double x_m, double yaw_deg) {
  return SE3d(Eigen::Quaterniond(Eigen::AngleAxisd(yaw_deg * std::numbers::pi / 180.0, Eigen::Vector3d::UnitY())),
              Eigen::Vector3d(x_m, 0.0, 0.0));
}

TEST(KeyframeAgreement, TheTruePlaceAgreesInDepthAndColour) {
  const SE3d T_W_K = pose(0.0, 0.0);
  const SE3d T_W_C = pose(0.05, 5.0);
  const loop::FernImage key_image = renderWall(T_W_K, true);
  const loop::FernImage frame = renderWall(T_W_C, true);
  const loop::KeyframeAgreement a = loop::keyframeAgreement(frame, keyframeOf(key_image, T_W_K),
                                                            T_W_K.inverse() * T_W_C, camera(), kFactor, kDepthGate_m);
  EXPECT_EQ(a.frame_blocks, 80 * 60);
  EXPECT_GT(a.overlap, a.frame_blocks * 8 / 10);
  EXPECT_EQ(a.depth_agreeing, a.overlap);
  EXPECT_GT(a.luma_ncc, 0.9);
  EXPECT_GT(a.frame_luma_std, 30.0);
}

TEST(KeyframeAgreement, APlaceSlidAlongTheWallAgreesInDepthButNotInColour) {
  const SE3d T_W_K = pose(0.0, 0.0);
  const SE3d T_W_C = pose(0.05, 5.0);
  const loop::FernImage key_image = renderWall(T_W_K, true);
  const loop::FernImage frame = renderWall(T_W_C, true);
  // Half a stripe period off along the wall: the depths still match, the stripes are in opposition.
  const SE3d T_W_C_slid = pose(0.05 + 0.5 * kStripePeriod_m, 5.0);
  const loop::KeyframeAgreement a = loop::keyframeAgreement(
      frame, keyframeOf(key_image, T_W_K), T_W_K.inverse() * T_W_C_slid, camera(), kFactor, kDepthGate_m);
  EXPECT_EQ(a.depth_agreeing, a.overlap);
  EXPECT_GT(a.overlap, a.frame_blocks / 2);
  EXPECT_LT(a.luma_ncc, -0.5);
}

TEST(KeyframeAgreement, ABlankWallCannotBeJudgedByColour) {
  const SE3d T_W_K = pose(0.0, 0.0);
  const loop::FernImage key_image = renderWall(T_W_K, false);
  const loop::FernImage frame = renderWall(T_W_K, false);
  const loop::KeyframeAgreement a =
      loop::keyframeAgreement(frame, keyframeOf(key_image, T_W_K), SE3d(), camera(), kFactor, kDepthGate_m);
  EXPECT_EQ(a.depth_agreeing, a.frame_blocks);
  EXPECT_EQ(a.luma_ncc, 0.0);
  EXPECT_LT(a.frame_luma_std, 1.0);
}

TEST(KeyframeAgreement, AWrongDepthDoesNotAgree) {
  const SE3d T_W_K = pose(0.0, 0.0);
  const loop::FernImage key_image = renderWall(T_W_K, true);
  const loop::FernImage frame = renderWall(T_W_K, true);
  // Placed 30 cm nearer the wall than it was: every pair overlaps, none within the 10 cm gate.
  const SE3d T_K_C(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.0, 0.0, 0.3));
  const loop::KeyframeAgreement a =
      loop::keyframeAgreement(frame, keyframeOf(key_image, T_W_K), T_K_C, camera(), kFactor, kDepthGate_m);
  EXPECT_GT(a.overlap, 0);
  EXPECT_EQ(a.depth_agreeing, 0);
}

TEST(KeyframeAgreement, RefusesABadFactorOrGate) {
  const loop::FernImage image = renderWall(SE3d(), true);
  const loop::FernKeyframe keyframe = keyframeOf(image, SE3d());
  EXPECT_THROW(loop::keyframeAgreement(image, keyframe, SE3d(), camera(), 0, kDepthGate_m), Error);
  EXPECT_THROW(loop::keyframeAgreement(image, keyframe, SE3d(), camera(), kFactor, 0.0), Error);
}

}  // namespace
}  // namespace vifusion
