// Model prediction on the GPU against its CPU reference (exact for splat ids and depth bits; 1e-5 m for
// positions), and against the data: a map made from a real 7-Scenes frame, rendered back at that frame's pose,
// reproduces the frame's vertex map. Map maintenance is in test_map_maintenance.cpp.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <random>
#include <utility>
#include <vector>

#include "gpu_test_environment.hpp"
#include "map_test_rig.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/map/map_buffers.hpp"
#include "vifusion/map/map_maintenance.hpp"
#include "vifusion/map/model_prediction.hpp"
#include "vifusion/preprocess/cpu_reference.hpp"
#include "vifusion/test/expect_error.hpp"
#include "vifusion/test/seven_scenes_frame.hpp"

namespace vifusion {
namespace {

double maxAbsDifference(ImageView<const Eigen::Vector4f> a, ImageView<const Eigen::Vector4f> b) {
  double worst = 0.0;
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) worst = std::max(worst, double((a(x, y) - b(x, y)).cwiseAbs().maxCoeff()));
  }
  return worst;
}

double maxAbsDifference(ImageView<const float> a, ImageView<const float> b) {
  double worst = 0.0;
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) worst = std::max(worst, double(std::abs(a(x, y) - b(x, y))));
  }
  return worst;
}

/// Expects the GPU prediction in `rig` to equal the CPU reference for `surfels` at every level.
void expectPredictionMatchesCpu(const MapRig& rig, std::span<const Surfel> surfels,
                                const map::PredictionParams& params) {
  const int w = params.view.width;
  const int h = params.view.height;
  Image<std::uint32_t> depth_bits(w, h), ids(w, h);
  map::splatModelCpu(surfels, params, depth_bits.view(), ids.view());
  EXPECT_EQ(countDifferent(rig.image<std::uint32_t>(rig.depthBits()), std::as_const(depth_bits).view()), 0u);
  EXPECT_EQ(countDifferent(rig.image<std::uint32_t>(rig.ids()), std::as_const(ids).view()), 0u);

  Vec4Image vertices0(w, h, Eigen::Vector4f::Zero()), normals0(w, h, Eigen::Vector4f::Zero());
  Image<float> intensity0(w, h);
  map::resolveModelCpu(surfels, params, ids.view(), vertices0.view(), normals0.view(), intensity0.view());
  for (int l = 0; l < rig.prediction().levels(); ++l) {
    SCOPED_TRACE("level " + std::to_string(l));
    const PinholeCamera& camera = rig.prediction().camera(l);
    Vec4Image vertices(camera.width, camera.height, Eigen::Vector4f::Zero());
    Vec4Image normals(camera.width, camera.height, Eigen::Vector4f::Zero());
    Image<float> intensity(camera.width, camera.height);
    map::subsampleModelCpu(vertices0.view(), normals0.view(), intensity0.view(), l, vertices.view(), normals.view(),
                           intensity.view());
    EXPECT_LE(maxAbsDifference(rig.image<Eigen::Vector4f>(rig.level(l).vertices, l), vertices.view()), 1e-5);
    EXPECT_LE(maxAbsDifference(rig.image<Eigen::Vector4f>(rig.level(l).normals, l), normals.view()), 1e-5);
    EXPECT_LE(maxAbsDifference(rig.image<float>(rig.level(l).intensity, l), intensity.view()), 1e-4);
  }
}

struct CameraCase {
  const char* name;
  double fy_sign;  ///< −1: ICL-NUIM-style negative fy
};
void PrintTo(const CameraCase& c, std::ostream* out) { *out << c.name; }

class MapPredictionTest : public GpuTest, public ::testing::WithParamInterface<CameraCase> {};

TEST_P(MapPredictionTest, RendersAFramesSurfelsBackIntoItsVertexMap) {
  test::SevenScenesFrame frame = test::loadSevenScenesFrame(150);
  frame.camera.fy *= GetParam().fy_sign;
  const FrameGeometry geometry = frameGeometry(frame);
  std::vector<Surfel> surfels = surfelsFromFrame(frame, geometry, 20.0f);
  const std::size_t real = surfels.size();
  // Distractors 10 cm in front of every 10th surfel, which would win every depth test if rendered:
  // inactive (updated 300 frames ago) and unstable (confidence 1) ones.
  const Eigen::Vector3f camera_W = frame.T_W_C.translation().cast<float>();
  for (std::size_t i = 0; i < real; i += 10) {
    Surfel inactive = movedToward(surfels[i], camera_W, 0.10f);
    inactive.colour_times.z() = static_cast<float>(kFrame - 300);
    Surfel unstable = movedToward(surfels[i + 5 < real ? i + 5 : i], camera_W, 0.10f);
    unstable.position_confidence.w() = 1.0f;
    surfels.push_back(inactive);
    surfels.push_back(unstable);
  }

  MapRig rig(context(), 400'000, frame.camera);
  rig.writeMap(surfels);
  const SE3d T_C_W = frame.T_W_C.inverse();
  rig.predict(T_C_W, kFrame);
  expectPredictionMatchesCpu(rig, surfels, rig.prediction().makeParams(T_C_W, kFrame));

  // Against the data: where the frame has a surfel, the model must be there, at the same depth.
  const auto model = rig.image<Eigen::Vector4f>(rig.level(0).vertices);
  std::size_t with_surfel = 0, covered = 0, within_5mm = 0;
  std::vector<float> errors_m;
  for (int y = 0; y < frame.camera.height; ++y) {
    for (int x = 0; x < frame.camera.width; ++x) {
      if (geometry.vertices(x, y).z() <= 0.0f || geometry.normals(x, y).isZero(0.0f)) continue;
      ++with_surfel;
      if (model(x, y).z() <= 0.0f) continue;
      ++covered;
      const float error_m = (model(x, y) - geometry.vertices(x, y)).head<3>().norm();
      errors_m.push_back(error_m);
      within_5mm += error_m <= 0.005f ? 1 : 0;
    }
  }
  ASSERT_GT(with_surfel, 100'000u);
  std::nth_element(errors_m.begin(), errors_m.begin() + errors_m.size() / 2, errors_m.end());
  const double coverage = double(covered) / double(with_surfel);
  const double fraction_5mm = double(within_5mm) / double(covered);
  std::cout << "coverage " << coverage << ", within 5 mm " << fraction_5mm << ", median error "
            << errors_m[errors_m.size() / 2] * 1000.0f << " mm\n";
  EXPECT_GE(coverage, 0.9);
  // The rest lie at depth edges and on curved or rippled surfaces, where a neighbouring disk's
  // tangent plane passes in front of this pixel's own surfel and wins the depth test.
  EXPECT_GE(fraction_5mm, 0.95);
  EXPECT_LE(errors_m[errors_m.size() / 2], 0.001f);
}

TEST_P(MapPredictionTest, RendersUnstableSurfelsOnlyWhileTheMapIsYoung) {
  test::SevenScenesFrame frame = test::loadSevenScenesFrame(175);
  frame.camera.fy *= GetParam().fy_sign;
  std::vector<Surfel> surfels = surfelsFromFrame(frame, frameGeometry(frame), 1.0f);
  MapRig rig(context(), 400'000, frame.camera);
  const SE3d T_C_W = frame.T_W_C.inverse();
  const map::PredictionOptions defaults;
  for (std::uint32_t render_frame : {defaults.young_map_frames - 1, defaults.young_map_frames}) {
    SCOPED_TRACE("frame " + std::to_string(render_frame));
    for (Surfel& s : surfels) s.colour_times.y() = s.colour_times.z() = static_cast<float>(render_frame);
    rig.writeMap(surfels);
    rig.predict(T_C_W, render_frame);
    expectPredictionMatchesCpu(rig, surfels, rig.prediction().makeParams(T_C_W, render_frame));
    const auto ids = rig.image<std::uint32_t>(rig.ids());
    const auto covered = static_cast<std::size_t>(
        std::count_if(ids.data, ids.data + ids.pixelCount(), [](std::uint32_t id) { return id != map::kNoSurfel; }));
    if (render_frame < defaults.young_map_frames) {
      EXPECT_GE(covered, surfels.size() * 9 / 10);
    } else {
      EXPECT_EQ(covered, 0u);
    }
  }
}

std::size_t pixelCount(const PinholeCamera& camera) { return std::size_t(camera.width) * std::size_t(camera.height); }

/// Kinds of surfel by activity (updated within δ_t) and stability (confidence ≥ threshold).
enum class Activity { ActiveStable, ActiveUnstable, InactiveStable, InactiveUnstable };

Activity activityOf(const Surfel& s, const map::PredictionParams& params) {
  const bool active = map::framesSinceCpu(params.view, s.colour_times.z()) <= params.time_window_frames;
  const bool stable = s.position_confidence.w() >= params.confidence_threshold;
  return active ? (stable ? Activity::ActiveStable : Activity::ActiveUnstable)
                : (stable ? Activity::InactiveStable : Activity::InactiveUnstable);
}

/// Per kind, how many pixels of the splat id image its surfels won.
std::array<std::size_t, 4> pixelsWonByKind(ImageView<const std::uint32_t> ids, std::span<const Surfel> surfels,
                                           const map::PredictionParams& params) {
  std::array<std::size_t, 4> won{};
  for (int y = 0; y < ids.height; ++y) {
    for (int x = 0; x < ids.width; ++x) {
      if (ids(x, y) != map::kNoSurfel) ++won[static_cast<std::size_t>(activityOf(surfels[ids(x, y)], params))];
    }
  }
  return won;
}

// A map whose surfels take turns being active and stable, active and unstable, inactive and stable (last updated
// 300 frames ago), inactive and unstable, with the inactive ones 5 cm in front so that they would win every
// depth test they took part in: the active prediction shows only active stable surfels (as before), the inactive
// one only inactive stable ones, the stable one (localisation-only) stable ones of both ages, each exactly as its
// CPU reference.
TEST_P(MapPredictionTest, EachPredictionRendersItsOwnSurfels) {
  test::SevenScenesFrame frame = test::loadSevenScenesFrame(150);
  frame.camera.fy *= GetParam().fy_sign;
  std::vector<Surfel> surfels = surfelsFromFrame(frame, frameGeometry(frame), 20.0f);
  const Eigen::Vector3f camera_W = frame.T_W_C.translation().cast<float>();
  constexpr std::uint32_t kInactiveAge = 300;  // > δ_t = 200
  for (std::size_t i = 0; i < surfels.size(); ++i) {
    const auto kind = static_cast<Activity>(i % 4);
    if (kind == Activity::ActiveUnstable || kind == Activity::InactiveUnstable) {
      surfels[i].position_confidence.w() = 1.0f;
    }
    if (kind == Activity::InactiveStable || kind == Activity::InactiveUnstable) {
      surfels[i] = movedToward(surfels[i], camera_W, 0.05f);
      surfels[i].colour_times.z() = static_cast<float>(kFrame - kInactiveAge);
    }
  }
  const SE3d T_C_W = frame.T_W_C.inverse();
  for (const map::PredictedSurfels set :
       {map::PredictedSurfels::kActive, map::PredictedSurfels::kInactive, map::PredictedSurfels::kStable}) {
    const bool inactive = set == map::PredictedSurfels::kInactive;
    const bool stable = set == map::PredictedSurfels::kStable;
    SCOPED_TRACE(stable ? "stable" : inactive ? "inactive" : "active");
    map::PredictionOptions options;
    options.surfels = set;
    MapRig rig(context(), 400'000, frame.camera, options);
    EXPECT_EQ(rig.prediction().surfels(), set);
    rig.writeMap(surfels);
    rig.predict(T_C_W, kFrame);
    const map::PredictionParams params = rig.prediction().makeParams(T_C_W, kFrame);
    EXPECT_EQ(params.surfels, static_cast<std::uint32_t>(set));
    expectPredictionMatchesCpu(rig, surfels, params);

    const std::array<std::size_t, 4> won = pixelsWonByKind(rig.image<std::uint32_t>(rig.ids()), surfels, params);
    // kStable shows both stable kinds; the inactive surfels, moved 5 cm towards the camera, win most pixels.
    const auto shown = static_cast<std::size_t>(inactive || stable ? Activity::InactiveStable : Activity::ActiveStable);
    for (std::size_t kind = 0; kind < won.size(); ++kind) {
      SCOPED_TRACE("kind " + std::to_string(kind));
      if (stable && kind == static_cast<std::size_t>(Activity::ActiveStable)) {
        EXPECT_GT(won[kind], 0u);  // where no inactive surfel is nearer
      } else if (kind == shown) {
        // A quarter of the frame's surfels, each disk √2 pixels wide: much of the image is covered.
        EXPECT_GE(won[kind], pixelCount(frame.camera) / 4);
      } else {
        EXPECT_EQ(won[kind], 0u);
      }
    }
  }
}

// The young-map rule (every active surfel before young_map_frames) is the active prediction's only: with a short
// time window that leaves inactive surfels in a young map, the inactive prediction still shows only stable ones.
TEST_P(MapPredictionTest, InactivePredictionIgnoresTheYoungMapRule) {
  test::SevenScenesFrame frame = test::loadSevenScenesFrame(175);
  frame.camera.fy *= GetParam().fy_sign;
  std::vector<Surfel> surfels = surfelsFromFrame(frame, frameGeometry(frame), 20.0f);
  map::MapOptions map_options = mapOptions(400'000);
  map_options.time_window_frames = 5;
  const map::PredictionOptions defaults;
  const std::uint32_t render_frame = defaults.young_map_frames - 1;
  for (std::size_t i = 0; i < surfels.size(); ++i) {
    if (i % 2 == 1) surfels[i].position_confidence.w() = 1.0f;  // unstable
    // Inactive at render_frame: 19 > 5 frames since the last update.
    surfels[i].colour_times.y() = surfels[i].colour_times.z() = 0.0f;
  }
  map::PredictionOptions options;
  options.surfels = map::PredictedSurfels::kInactive;
  MapRig rig(context(), 400'000, frame.camera, options, &map_options);
  rig.writeMap(surfels);
  const SE3d T_C_W = frame.T_W_C.inverse();
  rig.predict(T_C_W, render_frame);
  const map::PredictionParams params = rig.prediction().makeParams(T_C_W, render_frame);
  ASSERT_LT(params.view.frame, params.young_map_frames);
  expectPredictionMatchesCpu(rig, surfels, params);
  const std::array<std::size_t, 4> won = pixelsWonByKind(rig.image<std::uint32_t>(rig.ids()), surfels, params);
  EXPECT_GE(won[static_cast<std::size_t>(Activity::InactiveStable)], pixelCount(frame.camera) / 4);
  EXPECT_EQ(won[static_cast<std::size_t>(Activity::InactiveUnstable)], 0u);
  EXPECT_EQ(won[static_cast<std::size_t>(Activity::ActiveStable)], 0u);
  EXPECT_EQ(won[static_cast<std::size_t>(Activity::ActiveUnstable)], 0u);
}

// One submission's selection (ModelPrediction::setView with a SurfelSelection): the inactive instance showing only
// the surfels created before a frame — a loaded map's, for their reactivation while the camera maps on — and the
// active instance showing every stable surfel (a camera entering a saved map is verified against the whole map),
// each exactly as its CPU reference; a selection that would change an instance's buffers' meaning is refused.
TEST_P(MapPredictionTest, OneSubmissionsSelectionRendersOnlyItsSurfels) {
  test::SevenScenesFrame frame = test::loadSevenScenesFrame(150);
  frame.camera.fy *= GetParam().fy_sign;
  std::vector<Surfel> surfels = surfelsFromFrame(frame, frameGeometry(frame), 20.0f);
  constexpr std::uint32_t kLoadedUntil = 100;  // the first frame of the run that loaded the map
  constexpr std::uint32_t kInactiveAge = 300;  // > δ_t = 200
  for (std::size_t i = 0; i < surfels.size(); ++i) {
    // Every surfel inactive and stable; the even ones the loaded map's, the odd ones mapped since.
    surfels[i].colour_times.y() = static_cast<float>(i % 2 == 0 ? kLoadedUntil - 1 : kLoadedUntil);
    surfels[i].colour_times.z() = static_cast<float>(kFrame - kInactiveAge);
  }
  const SE3d T_C_W = frame.T_W_C.inverse();
  map::PredictionOptions options;
  options.surfels = map::PredictedSurfels::kInactive;
  MapRig rig(context(), 400'000, frame.camera, options);
  rig.writeMap(surfels);
  map::SurfelSelection loaded;
  loaded.surfels = map::PredictedSurfels::kInactive;
  loaded.created_before = kLoadedUntil;
  rig.prediction().setView(T_C_W, kFrame, loaded);
  rig.runPrediction();
  map::PredictionParams params = rig.prediction().makeParams(T_C_W, kFrame);
  EXPECT_EQ(params.created_before, map::kAnyCreationFrame);
  params.created_before = kLoadedUntil;
  expectPredictionMatchesCpu(rig, surfels, params);
  const ImageView<const std::uint32_t> ids = rig.image<std::uint32_t>(rig.ids());
  std::size_t loaded_won = 0, later_won = 0;
  for (int y = 0; y < ids.height; ++y) {
    for (int x = 0; x < ids.width; ++x) {
      if (ids(x, y) == map::kNoSurfel) continue;
      ++(ids(x, y) % 2 == 0 ? loaded_won : later_won);
    }
  }
  EXPECT_GE(loaded_won, pixelCount(frame.camera) / 4);
  EXPECT_EQ(later_won, 0u);

  map::SurfelSelection every_stable;
  every_stable.surfels = map::PredictedSurfels::kStable;
  test::expectError([&] { rig.prediction().setView(T_C_W, kFrame, every_stable); },
                    "only the inactive instance renders the inactive surfels, and only them");
  MapRig active_rig(context(), 400'000, frame.camera, map::PredictionOptions{});
  active_rig.writeMap(surfels);
  active_rig.prediction().setView(T_C_W, kFrame, every_stable);
  active_rig.runPrediction();
  params = active_rig.prediction().makeParams(T_C_W, kFrame);
  params.surfels = static_cast<std::uint32_t>(map::PredictedSurfels::kStable);
  expectPredictionMatchesCpu(active_rig, surfels, params);
  test::expectError([&] { active_rig.prediction().setView(T_C_W, kFrame, loaded); },
                    "only the inactive instance renders the inactive surfels, and only them");
}

TEST(PredictionOptions, ValidateNamesTheSurfelsField) {
  EXPECT_EQ(map::PredictionOptions{}.surfels, map::PredictedSurfels::kActive);
  map::PredictionOptions options;
  options.surfels = map::PredictedSurfels::kInactive;
  EXPECT_NO_THROW(options.validate());
  options.surfels = map::PredictedSurfels::kStable;
  EXPECT_NO_THROW(options.validate());
  options.surfels = static_cast<map::PredictedSurfels>(3);
  test::expectError([&] { options.validate(); }, "prediction option 'surfels' must be kActive, kInactive or kStable");
}

INSTANTIATE_TEST_SUITE_P(Cameras, MapPredictionTest,
                         ::testing::Values(CameraCase{"kinect", 1.0}, CameraCase{"negative_fy", -1.0}),
                         [](const ::testing::TestParamInfo<CameraCase>& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace vifusion
