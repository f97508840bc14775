#include "vifusion/slam/map_saving.hpp"

#include <chrono>

#include "vifusion/core/error.hpp"
#include "vifusion/mapfile/map_file_writer.hpp"

namespace vifusion::slam {

static_assert(sizeof(map::Surfel) == mapfile::kSurfelFloats * sizeof(float),
              "the map file stores a surfel as the GPU record's 32-bit words");

MapSaveReport saveMap(Slam& slam, const MapSaveInputs& inputs, const std::string& path) {
  if (inputs.calibration == nullptr) throw Error("map file " + path + ": saved without the calibration");
  const auto start = std::chrono::steady_clock::now();
  mapfile::MapFileWriter writer(path);
  mapfile::MapMeta meta;
  meta.mode = slamModeName(inputs.mode);
  meta.frames = static_cast<std::uint32_t>(inputs.trajectory.size());
  if (!inputs.trajectory.empty()) {
    meta.first_t_ns = inputs.trajectory.front().t_ns;
    meta.last_t_ns = inputs.trajectory.back().t_ns;
  }
  mapfile::writeMeta(writer, meta);
  mapfile::writeCalibration(writer, *inputs.calibration);
  mapfile::writeState(writer, inputs.state);
  mapfile::writeTrajectory(writer, inputs.trajectory);
  const loop::FernDatabase* keyframes = slam.keyframeDatabase();
  mapfile::writeKeyframes(writer, keyframes);

  const map::MapState state = slam.mapState();
  mapfile::beginSurfels(writer, {state.surfel_count, state.active_begin, state.frame});
  const std::uint32_t visited = slam.visitMap([&writer](std::uint32_t, std::span<const map::Surfel> chunk) {
    writer.putF32s({reinterpret_cast<const float*>(chunk.data()), chunk.size() * mapfile::kSurfelFloats});
  });
  if (visited != state.surfel_count)
    throw Error("map file " + path + ": the map held " + std::to_string(visited) + " surfels, its state said " +
                std::to_string(state.surfel_count));
  writer.endSection();

  MapSaveReport report;
  report.bytes = writer.commit();
  report.surfels = visited;
  report.keyframes = keyframes != nullptr ? keyframes->size() : 0;
  report.elapsed_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace vifusion::slam
