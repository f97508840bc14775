#include "vifusion/slam/map_saving.hpp"

#include <chrono>
#include <functional>

#include "vifusion/core/error.hpp"
#include "vifusion/core/resident_memory.hpp"
#include "vifusion/mapfile/map_file_writer.hpp"

namespace vifusion::slam {
namespace {

static_assert(sizeof(map::Surfel) == mapfile::kSurfelFloats * sizeof(float),
              "the map file stores a surfel as the GPU record's 32-bit words");

/// Surfels a snapshot hands the writer per putF32s: the export's chunk size is the GPU's concern, this one
/// only bounds each call (the writer buffers either way).
constexpr std::size_t kSnapshotChunkSurfels = 16'384;

double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// Puts one chunk of surfels into the section being written.
void putSurfels(mapfile::MapFileWriter& writer, std::span<const map::Surfel> chunk) {
  writer.putF32s({reinterpret_cast<const float*>(chunk.data()), chunk.size() * mapfile::kSurfelFloats});
}

/// The one encoding of a map file; `put_surfels` puts the surfels section's records and returns their count.
MapSaveReport writeSections(const std::string& path, SlamMode mode, const RigCalibration& calibration,
                            std::span<const mapfile::StampedPose> trajectory, const std::optional<NavState>& state,
                            const loop::FernDatabase* keyframes, const map::MapState& map_state,
                            std::uint32_t frame_clock,
                            const std::function<std::uint32_t(mapfile::MapFileWriter&)>& put_surfels) {
  const auto start = std::chrono::steady_clock::now();
  mapfile::MapFileWriter writer(path);
  mapfile::MapMeta meta;
  meta.mode = slamModeName(mode);
  meta.frames = frame_clock;
  if (!trajectory.empty()) {
    meta.first_t_ns = trajectory.front().t_ns;
    meta.last_t_ns = trajectory.back().t_ns;
  }
  mapfile::writeMeta(writer, meta);
  mapfile::writeCalibration(writer, calibration);
  mapfile::writeState(writer, state);
  mapfile::writeTrajectory(writer, trajectory);
  mapfile::writeKeyframes(writer, keyframes);
  mapfile::beginSurfels(writer, {map_state.surfel_count, map_state.active_begin, map_state.frame});
  const std::uint32_t put = put_surfels(writer);
  if (put != map_state.surfel_count)
    throw Error("map file " + path + ": the map held " + std::to_string(put) + " surfels, its state said " +
                std::to_string(map_state.surfel_count));
  writer.endSection();

  MapSaveReport report;
  report.bytes = writer.commit();
  report.surfels = put;
  report.keyframes = keyframes != nullptr ? keyframes->size() : 0;
  report.elapsed_ms = millisecondsSince(start);
  return report;
}

}  // namespace

void MapSnapshot::reserve(std::uint32_t surfel_capacity, std::size_t frames) {
  // A full map's worth, resident from start-up rather than page by page as the map grows (resident_memory.hpp).
  reserveResident(surfels, surfel_capacity, map::Surfel{});
  reserveResident(trajectory, frames, mapfile::StampedPose{});
}

MapSaveReport saveMap(Slam& slam, const MapSaveInputs& inputs, const std::string& path) {
  if (inputs.calibration == nullptr) throw Error("map file " + path + ": saved without the calibration");
  return writeSections(path, inputs.mode, *inputs.calibration, inputs.trajectory, inputs.state, slam.keyframeDatabase(),
                       slam.mapState(), slam.frameClock(), [&slam](mapfile::MapFileWriter& writer) {
                         return slam.visitMap([&writer](std::uint32_t, std::span<const map::Surfel> chunk) {
                           putSurfels(writer, chunk);
                         });
                       });
}

void captureMap(Slam& slam, const MapSaveInputs& inputs, MapSnapshot& snapshot) {
  if (inputs.calibration == nullptr) throw Error("map snapshot: captured without the calibration");
  const auto start = std::chrono::steady_clock::now();
  snapshot.mode = inputs.mode;
  snapshot.calibration = *inputs.calibration;
  snapshot.trajectory.assign(inputs.trajectory.begin(), inputs.trajectory.end());
  snapshot.state = inputs.state;
  if (const loop::FernDatabase* keyframes = slam.keyframeDatabase()) {
    // Assigning over a database of the same capacity copies into its storage: no allocation after the first.
    if (snapshot.keyframes) {
      *snapshot.keyframes = *keyframes;
    } else {
      snapshot.keyframes.emplace(*keyframes);
    }
  } else {
    snapshot.keyframes.reset();
  }
  snapshot.map_state = slam.mapState();
  snapshot.frame_clock = slam.frameClock();
  slam.exportMap(snapshot.surfels);
  snapshot.capture_ms = millisecondsSince(start);
}

MapSaveReport writeMapFile(const MapSnapshot& snapshot, const std::string& path) {
  const loop::FernDatabase* keyframes = snapshot.keyframes ? &*snapshot.keyframes : nullptr;
  return writeSections(path, snapshot.mode, snapshot.calibration, snapshot.trajectory, snapshot.state, keyframes,
                       snapshot.map_state, snapshot.frame_clock, [&snapshot](mapfile::MapFileWriter& writer) {
                         const std::span<const map::Surfel> all(snapshot.surfels);
                         for (std::size_t first = 0; first < all.size(); first += kSnapshotChunkSurfels) {
                           putSurfels(writer, all.subspan(first, std::min(kSnapshotChunkSurfels, all.size() - first)));
                         }
                         return static_cast<std::uint32_t>(all.size());
                       });
}

}  // namespace vifusion::slam
