// Relocalisation's place memory (slam/relocaliser.hpp): the fern image size it picks per resolution, which
// frames become keyframes, which keyframe a lost frame is matched to (and that an unknown view matches none),
// the gate on recoveries that assume the camera came back to the last tracked view, moving keyframes with a
// closure, option validation and the per-frame path's heap use. Frames are synthetic box scenes (CPU only).

#include <gtest/gtest.h>

#include <cstdint>
#include <optional>

#include "vifusion/slam/relocaliser.hpp"
#include "vifusion/test/box_scene.hpp"
#include "vifusion/test/counting_allocations.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion::slam {
namespace {

constexpr int kWidth = 640;
constexpr int kHeight = 480;

SE3d poseAt(double x_m) { return SE3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(x_m, 0.0, 0.0)); }

TEST(RelocalisationOptions, ValidationNamesTheField) {
  EXPECT_NO_THROW(RelocalisationOptions{}.validate());
  RelocalisationOptions options;
  options.fern_image_width = 0;
  test::expectError([&] { options.validate(); }, "'fern_image_width'");
  options = RelocalisationOptions{};
  options.ferns.num_ferns = 0;
  test::expectError([&] { options.validate(); }, "'num_ferns'");
}

TEST(Relocaliser, FernsSeeAboutEightyPixelsWhateverTheResolution) {
  const RelocalisationOptions options;
  EXPECT_EQ(Relocaliser(options, 640, 480).downsampleFactor(), 8);
  EXPECT_EQ(Relocaliser(options, 320, 240).downsampleFactor(), 4);
  EXPECT_EQ(Relocaliser(options, 160, 120).downsampleFactor(), 2);
  // The 60 Hz preset: 480 / 80 = 6 divides 360 too, so 80×60 again.
  EXPECT_EQ(Relocaliser(options, 480, 360).downsampleFactor(), 6);
  // 100×75: 100 / 80 = 1, nothing to average.
  EXPECT_EQ(Relocaliser(options, 100, 75).downsampleFactor(), 1);
}

TEST(Relocaliser, MatchesALostFrameToTheKeyframeOfItsPlace) {
  Relocaliser relocaliser(RelocalisationOptions{}, kWidth, kHeight);
  constexpr std::uint32_t kPlaces = 5;
  for (std::uint32_t place = 0; place < kPlaces; ++place) {
    relocaliser.encode(test::makeBoxScene(10 + place, kWidth, kHeight));
    relocaliser.offer(poseAt(place), static_cast<std::int64_t>(place) * 1000, 30 * place);
    // The same view again a frame later is not novel: no second keyframe.
    relocaliser.encode(test::noisyCopy(test::makeBoxScene(10 + place, kWidth, kHeight), 3, place));
    relocaliser.offer(poseAt(place + 0.01), static_cast<std::int64_t>(place) * 1000 + 33, 30 * place + 1);
  }
  EXPECT_EQ(relocaliser.keyframes(), static_cast<int>(kPlaces));

  // Coming back to place 3 (other exposure, other noise) finds its keyframe, pose and frame.
  relocaliser.encode(test::noisyCopy(test::makeBoxScene(13, kWidth, kHeight), -6, 77));
  const std::optional<PlaceCandidate> place = relocaliser.candidate();
  ASSERT_TRUE(place.has_value());
  EXPECT_EQ(place->keyframe, 3);
  EXPECT_EQ(place->frame_index, 90u);
  EXPECT_NEAR(place->T_W_C.translation().x(), 3.0, 1e-12);
  EXPECT_LT(place->dissimilarity, RelocalisationOptions{}.ferns.keyframe_threshold);

  // A view of somewhere never seen matches nothing: the caller stays lost rather than jump.
  relocaliser.encode(test::makeBoxScene(999, kWidth, kHeight));
  EXPECT_FALSE(relocaliser.candidate().has_value());
  // Nor does a covered camera (no depth, black): too few valid ferns to compare.
  RgbdFrame covered = test::makeBoxScene(13, kWidth, kHeight);
  covered.rgb.resize(kWidth, kHeight, Rgb8{0, 0, 0});
  covered.depth.resize(kWidth, kHeight, 0);
  relocaliser.encode(covered);
  EXPECT_FALSE(relocaliser.candidate().has_value());
}

TEST(Relocaliser, ARecoveryMustSeeTheLastTrackedView) {
  Relocaliser relocaliser(RelocalisationOptions{}, kWidth, kHeight);
  const RgbdFrame last = test::makeBoxScene(1, kWidth, kHeight);
  relocaliser.encode(last);
  EXPECT_FALSE(relocaliser.looksLikeLastTracked()) << "nothing tracked yet";
  relocaliser.offer(poseAt(0.0), 0, 0);
  relocaliser.encode(test::noisyCopy(last, 5, 2));
  EXPECT_TRUE(relocaliser.looksLikeLastTracked());
  relocaliser.encode(test::makeBoxScene(2, kWidth, kHeight));
  EXPECT_FALSE(relocaliser.looksLikeLastTracked());
}

TEST(Relocaliser, KeyframesMoveWithTheMap) {
  Relocaliser relocaliser(RelocalisationOptions{}, kWidth, kHeight);
  for (std::uint32_t place = 0; place < 3; ++place) {
    relocaliser.encode(test::makeBoxScene(40 + place, kWidth, kHeight));
    relocaliser.offer(poseAt(place), 0, 10 * place);
  }
  ASSERT_EQ(relocaliser.keyframes(), 3);
  // A closure that moves frames after 15 by 5 cm along y.
  relocaliser.moveKeyframes([](const SE3d& T_W_C, std::uint32_t frame) {
    return frame > 15 ? SE3d(T_W_C.quaternion(), T_W_C.translation() + Eigen::Vector3d(0.0, 0.05, 0.0)) : T_W_C;
  });
  relocaliser.encode(test::makeBoxScene(42, kWidth, kHeight));
  const std::optional<PlaceCandidate> moved = relocaliser.candidate();
  ASSERT_TRUE(moved.has_value());
  EXPECT_NEAR(moved->T_W_C.translation().y(), 0.05, 1e-12);
  relocaliser.encode(test::makeBoxScene(40, kWidth, kHeight));
  const std::optional<PlaceCandidate> kept = relocaliser.candidate();
  ASSERT_TRUE(kept.has_value());
  EXPECT_EQ(kept->T_W_C.translation().y(), 0.0);
}

TEST(Relocaliser, PerFramePathAllocatesNothing) {
  Relocaliser relocaliser(RelocalisationOptions{}, kWidth, kHeight);
  const RgbdFrame a = test::makeBoxScene(60, kWidth, kHeight);
  const RgbdFrame b = test::makeBoxScene(61, kWidth, kHeight);
  const std::uint64_t before = test::heapAllocationCount();
  for (std::uint32_t frame = 0; frame < 20; ++frame) {
    relocaliser.encode(frame % 2 == 0 ? a : b);
    relocaliser.offer(poseAt(frame), frame, frame);
    static_cast<void>(relocaliser.candidate());
    static_cast<void>(relocaliser.looksLikeLastTracked());
  }
  EXPECT_EQ(test::heapAllocationCount(), before);
  EXPECT_EQ(relocaliser.keyframes(), 2);
}

}  // namespace
}  // namespace vifusion::slam
