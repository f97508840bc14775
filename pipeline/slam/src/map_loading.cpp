// Slam::loadMap (map_loading.hpp): kept apart from slam.cpp, which holds the per-frame pipeline.
#include <chrono>

#include "vifusion/core/error.hpp"
#include "vifusion/mapfile/map_file_reader.hpp"
#include "vifusion/mapfile/map_sections.hpp"
#include "vifusion/slam/slam.hpp"

namespace vifusion::slam {

static_assert(sizeof(map::Surfel) == mapfile::kSurfelFloats * sizeof(float),
              "the map file stores a surfel as the GPU record's 32-bit words");

MapLoadReport Slam::loadMap(const std::string& path) {
  if (frame_index_ != 0) throw Error("map file " + path + ": a map is loaded before the first frame, not during a run");
  if (!relocaliser_) {
    throw Error("map file " + path + ": relocalisation is off in this run, and a loaded map is entered only by it");
  }
  if (!loop_closure_) {
    throw Error("map file " + path +
                ": loop closure is off in this run, and its reactivation is what brings a loaded map's surfels "
                "back into use");
  }
  const auto start = std::chrono::steady_clock::now();
  MapLoadReport report;
  try {
    mapfile::MapFileReader reader(path);
    const mapfile::MapMeta meta = mapfile::readMeta(reader);
    const RigCalibration saved = mapfile::readCalibration(reader);
    const int width = map_->width(), height = map_->height();
    if (saved.camera.width != width || saved.camera.height != height) {
      reader.fail("the map was built with a " + std::to_string(saved.camera.width) + "x" +
                  std::to_string(saved.camera.height) + " camera, this run's is " + std::to_string(width) + "x" +
                  std::to_string(height));
    }
    report.state = mapfile::readState(reader);
    // The old poses are kept in the file for its users; a run takes only their heights (the map search's).
    const std::vector<mapfile::StampedPose> trajectory = mapfile::readTrajectory(reader);
    std::optional<loop::FernDatabase> keyframes = mapfile::readKeyframes(reader);
    if (!keyframes || keyframes->size() == 0)
      reader.fail("no keyframes to relocalise against (the map was saved with relocalisation off)");
    report.keyframes = keyframes->size();
    relocaliser_->replaceDatabase(std::move(*keyframes));
    const mapfile::SurfelsHeader surfels = mapfile::beginSurfels(reader);
    // The map search needs the stable surfaces on the host (inertial modes: it needs the saved gravity).
    const bool search = relocalisation_.map_search && estimator_ && report.state;
    std::vector<Eigen::Vector3f> stable_W;
    const float stable_confidence = map_->options().confidence_threshold;
    importer_->load(surfels.surfel_count, surfels.frame, [&](std::uint32_t, std::span<map::Surfel> chunk) {
      reader.getF32s({reinterpret_cast<float*>(chunk.data()), chunk.size() * mapfile::kSurfelFloats});
      if (!search) return;
      for (const map::Surfel& surfel : chunk) {
        if (surfel.position_confidence.w() >= stable_confidence)
          stable_W.push_back(surfel.position_confidence.head<3>());
      }
    });
    reader.endSection();
    reader.finish();
    if (search) prepareMapSearch(stable_W, trajectory, *report.state);
    report.mode = meta.mode;
    report.frames = meta.frames;
    report.bytes = reader.fileBytes();
    report.surfels = surfels.surfel_count;
    // The map's clock continues: the saved surfels and keyframes keep their ages.
    first_frame_index_ = surfels.frame + 1;
  } catch (...) {
    map_->reset(*arena_);
    relocaliser_->reset();
    map_search_.reset();
    throw;
  }
  frame_index_ = first_frame_index_;
  report.first_frame = first_frame_index_;
  loaded_state_ = report.state;
  relocalising_ = true;
  map_loaded_ = true;
  report.elapsed_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace vifusion::slam
