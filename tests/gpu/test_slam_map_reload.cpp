// A map that outlives its run (slam/map_saving.hpp, slam/map_loading.hpp), end to end on the GPU: a run maps
// the rendered pan and saves; a second Slam loads the file, relocalises its first frame into the saved map by
// the saved keyframes, and tracks on in the saved map's frame without mapping the pan a second time. A file made
// for another camera is refused by name, and the Slam then runs as a fresh one.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "gpu_test_environment.hpp"
#include "rendered_pan.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/slam/map_saving.hpp"
#include "vifusion/slam/slam.hpp"
#include "vifusion/test/counting_allocations.hpp"

namespace vifusion {
namespace {

using test::GpuTest;

constexpr std::int64_t kFramePeriod_ns = 33'333'333;

std::string temporaryMap(const std::string& name) {
  // One directory per process: ctest runs the plain, validation and no-subgroups variants of a test at once.
  const std::filesystem::path directory =
      std::filesystem::path(::testing::TempDir()) / ("vifusion_reload_" + std::to_string(::getpid()));
  std::filesystem::create_directories(directory);
  return (directory / name).string();
}

RgbdFrame panFrame(const test::Pan& pan, std::size_t k, std::uint32_t i) {
  RgbdFrame frame = pan.frames[k];
  frame.t_ns = static_cast<std::int64_t>(i) * kFramePeriod_ns;
  frame.index = i;
  return frame;
}

/// Maps the pan forwards once and saves the map; returns the surfels and keyframes saved.
slam::MapSaveReport mapAndSave(gpu::GpuContext& context, const RigCalibration& calibration, const test::Pan& pan,
                               const std::string& path) {
  slam::Slam slam(context, calibration, slam::SlamOptions{});
  std::vector<mapfile::StampedPose> trajectory;
  for (std::uint32_t i = 0; i < pan.frames.size(); ++i) {
    const slam::FrameResult result = slam.process(panFrame(pan, i, i));
    EXPECT_FALSE(result.lost()) << "frame " << i;
    trajectory.push_back({result.t_ns, result.T_W_C});
  }
  return slam::saveMap(slam, {slam::SlamMode::kRgbd, &calibration, trajectory, std::nullopt}, path);
}

TEST_F(GpuTest, ASavedMapIsReloadedRelocalisedIntoAndTrackedInItsOwnFrame) {
  const RigCalibration calibration = test::panCalibration();
  const test::Pan pan = test::renderPan(calibration.camera);
  const std::string path = temporaryMap("pan.vifmap");
  const slam::MapSaveReport saved = mapAndSave(context(), calibration, pan, path);
  ASSERT_GT(saved.surfels, 0u);
  ASSERT_GT(saved.keyframes, 0);

  slam::Slam slam(context(), calibration, slam::SlamOptions{});
  const slam::MapLoadReport loaded = slam.loadMap(path);
  EXPECT_EQ(loaded.surfels, saved.surfels);
  EXPECT_EQ(loaded.keyframes, saved.keyframes);
  EXPECT_EQ(loaded.mode, "rgbd");
  EXPECT_EQ(loaded.bytes, std::filesystem::file_size(path));
  EXPECT_EQ(slam.firstFrameIndex(), pan.frames.size());  // the saved clock's next frame
  EXPECT_EQ(loaded.frames, pan.frames.size());

  // The second run starts a few frames into the pan and goes back and forth over it.
  constexpr std::size_t kStart = 4;
  constexpr std::uint32_t kFrames = 60;
  // W is the saved run's first camera.
  const SE3d T_W_living = pan.T_W_C[0].inverse();
  double worst_m = 0.0;
  int relocalising = 0;
  std::uint32_t surfels = 0;
  for (std::uint32_t i = 0; i < kFrames; ++i) {
    const std::size_t k = test::panFrameIndex(kStart + i, pan.frames.size());
    const slam::FrameResult result = slam.process(panFrame(pan, k, i));
    if (result.relocalising) {
      ++relocalising;
      EXPECT_EQ(result.surfels, saved.surfels) << "frame " << i << ": nothing is fused before the camera is located";
      continue;
    }
    EXPECT_FALSE(result.lost()) << "frame " << i;
    if (i == static_cast<std::uint32_t>(relocalising)) {
      EXPECT_TRUE(result.relocalised);
    }
    worst_m = std::max(worst_m, ((T_W_living * pan.T_W_C[k]).translation() - result.T_W_C.translation()).norm());
    surfels = result.surfels;
  }
  std::printf(
      "  reloaded: %u surfels, %d keyframes, loaded in %.0f ms; %d frames relocalising, worst position "
      "error %.1f mm in the saved frame; surfels %u → %u\n",
      loaded.surfels, loaded.keyframes, loaded.elapsed_ms, relocalising, worst_m * 1e3, saved.surfels, surfels);
  EXPECT_EQ(relocalising, 0);  // the first frame is a few pan steps from the first keyframe
  EXPECT_LT(worst_m, 0.01);
  // The same surfaces again: fused into the loaded surfels, not mapped a second time.
  EXPECT_LT(surfels, saved.surfels + saved.surfels / 10);

  // Saved again, the map's clock counts both runs' frames, and a run that loads it continues the clock.
  const std::string again = temporaryMap("pan_again.vifmap");
  const std::vector<mapfile::StampedPose> no_poses;
  slam::saveMap(slam, {slam::SlamMode::kRgbd, &calibration, no_poses, std::nullopt}, again);
  slam::Slam third(context(), calibration, slam::SlamOptions{});
  EXPECT_EQ(third.loadMap(again).frames, pan.frames.size() + kFrames);
  EXPECT_EQ(third.firstFrameIndex(), pan.frames.size() + kFrames);
}

// Localisation only: the pan tracked against the loaded map in its frame, and the map on the GPU still the file's
// surfels bit for bit after 60 frames (nothing fused, aged, removed or deformed).
TEST_F(GpuTest, LocalisationOnlyTracksInTheLoadedMapAndLeavesItAsLoaded) {
  const RigCalibration calibration = test::panCalibration();
  const test::Pan pan = test::renderPan(calibration.camera);
  const std::string path = temporaryMap("pan_localisation.vifmap");
  const slam::MapSaveReport saved = mapAndSave(context(), calibration, pan, path);

  slam::SlamOptions options;
  options.mapping = false;
  slam::Slam slam(context(), calibration, options);
  slam.loadMap(path);
  std::vector<map::Surfel> loaded;
  slam.exportMap(loaded);
  const map::MapState loaded_state = slam.mapState();
  ASSERT_EQ(loaded.size(), saved.surfels);

  constexpr std::size_t kStart = 4;
  constexpr std::uint32_t kFrames = 60;
  const SE3d T_W_living = pan.T_W_C[0].inverse();
  double worst_m = 0.0;
  int lost = 0;
  for (std::uint32_t i = 0; i < kFrames; ++i) {
    const std::size_t k = test::panFrameIndex(kStart + i, pan.frames.size());
    const slam::FrameResult result = slam.process(panFrame(pan, k, i));
    ASSERT_FALSE(result.relocalising) << "frame " << i;
    lost += result.lost() ? 1 : 0;
    if (!result.lost()) {
      worst_m = std::max(worst_m, ((T_W_living * pan.T_W_C[k]).translation() - result.T_W_C.translation()).norm());
    }
    EXPECT_EQ(result.surfels, saved.surfels) << "frame " << i;
  }
  std::printf("  localisation only: %d of %u frames lost, worst position error %.1f mm in the saved frame\n", lost,
              kFrames, worst_m * 1e3);
  EXPECT_EQ(lost, 0);
  EXPECT_LT(worst_m, 0.01);
  std::vector<map::Surfel> after;
  slam.exportMap(after);
  const map::MapState after_state = slam.mapState();
  EXPECT_EQ(after_state.surfel_count, loaded_state.surfel_count);
  EXPECT_EQ(after_state.active_begin, loaded_state.active_begin);
  EXPECT_EQ(after_state.frame, loaded_state.frame);
  ASSERT_EQ(after.size(), loaded.size());
  EXPECT_EQ(std::memcmp(after.data(), loaded.data(), loaded.size() * sizeof(map::Surfel)), 0);
}

TEST_F(GpuTest, LocalisationOnlyWithoutALoadedMapIsRefusedByName) {
  const RigCalibration calibration = test::panCalibration();
  const test::Pan pan = test::renderPan(calibration.camera);
  slam::SlamOptions options;
  options.mapping = false;
  slam::Slam slam(context(), calibration, options);
  try {
    slam.process(panFrame(pan, 0, 0));
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("localisation only (mapping off) needs a loaded map"), std::string::npos)
        << error.what();
  }
}

std::vector<char> fileBytes(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

// The service's way (a capture on the SLAM thread, the write on another) writes the file the streaming save would
// have written at that moment, byte for byte; and once reserved, a capture allocates nothing on the host.
TEST_F(GpuTest, ACapturedMapIsWrittenAsTheStreamingSaveWritesIt) {
  const RigCalibration calibration = test::panCalibration();
  const test::Pan pan = test::renderPan(calibration.camera);
  slam::Slam slam(context(), calibration, slam::SlamOptions{});
  std::vector<mapfile::StampedPose> trajectory;
  trajectory.reserve(pan.frames.size());
  slam::MapSnapshot snapshot;
  snapshot.reserve(slam::SlamOptions{}.map.capacity, pan.frames.size());
  std::uint64_t capture_allocations = 0;
  for (std::uint32_t i = 0; i < pan.frames.size(); ++i) {
    const slam::FrameResult result = slam.process(panFrame(pan, i, i));
    trajectory.push_back({result.t_ns, result.T_W_C});
    const slam::MapSaveInputs inputs{slam::SlamMode::kRgbd, &calibration, trajectory, std::nullopt};
    const std::uint64_t before = test::heapAllocationCount();
    slam::captureMap(slam, inputs, snapshot);
    // The first capture makes the keyframe database's copy; later ones copy into it.
    if (i > 0) capture_allocations += test::heapAllocationCount() - before;
  }
  EXPECT_EQ(capture_allocations, 0u);
  const std::string streamed = temporaryMap("pan_streamed.vifmap");
  const std::string captured = temporaryMap("pan_captured.vifmap");
  const slam::MapSaveReport saved =
      slam::saveMap(slam, {slam::SlamMode::kRgbd, &calibration, trajectory, std::nullopt}, streamed);
  const slam::MapSaveReport written = slam::writeMapFile(snapshot, captured);
  EXPECT_EQ(written.bytes, saved.bytes);
  EXPECT_EQ(written.surfels, saved.surfels);
  EXPECT_EQ(written.keyframes, saved.keyframes);
  EXPECT_GT(saved.keyframes, 0);
  EXPECT_TRUE(fileBytes(captured) == fileBytes(streamed));
  EXPECT_GT(snapshot.capture_ms, 0.0);
}

TEST_F(GpuTest, AMapOfAnotherCameraIsRefusedAndTheRunStartsFresh) {
  const RigCalibration calibration = test::panCalibration();
  const test::Pan pan = test::renderPan(calibration.camera);
  const std::string path = temporaryMap("pan_for_other_camera.vifmap");
  mapAndSave(context(), calibration, pan, path);

  RigCalibration other = calibration;
  other.camera = PinholeCamera::create(320, 240, 240.0, 240.0, 159.5, 119.5);
  slam::Slam slam(context(), other, slam::SlamOptions{});
  try {
    slam.loadMap(path);
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what())
                  .find("section 'calib': the map was built with a 160x120 camera, this run's "
                        "is 320x240"),
              std::string::npos)
        << error.what();
  }
  EXPECT_EQ(slam.firstFrameIndex(), 0u);
  EXPECT_EQ(slam.mapState().surfel_count, 0u);
}

TEST_F(GpuTest, ACutMapFileIsRefusedByItsSectionAndNothingOfItStays) {
  // Cut in the surfels, after the keyframes were taken in and part of the surfels uploaded: the load is undone,
  // and the run maps from scratch (the first frame defines W, nothing is relocalising).
  const RigCalibration calibration = test::panCalibration();
  const test::Pan pan = test::renderPan(calibration.camera);
  const std::string path = temporaryMap("pan_cut.vifmap");
  mapAndSave(context(), calibration, pan, path);
  std::filesystem::resize_file(path, std::filesystem::file_size(path) - 1000);

  slam::Slam slam(context(), calibration, slam::SlamOptions{});
  try {
    slam.loadMap(path);
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("section 'surfels': cut"), std::string::npos) << error.what();
  }
  EXPECT_EQ(slam.mapState().surfel_count, 0u);
  EXPECT_EQ(slam.keyframes(), 0);
  EXPECT_EQ(slam.firstFrameIndex(), 0u);
  const slam::FrameResult first = slam.process(panFrame(pan, 0, 0));
  EXPECT_FALSE(first.relocalising);
  EXPECT_FALSE(first.lost());
  EXPECT_GT(first.surfels, 0u);

  slam::SlamOptions open_loop;
  open_loop.loop.enabled = false;
  slam::Slam without_loop_closure(context(), calibration, open_loop);
  EXPECT_THROW(without_loop_closure.loadMap(path), Error);
}

}  // namespace
}  // namespace vifusion
