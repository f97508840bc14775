#pragma once
// Saving the running map to a map file (mapfile/map_sections.hpp): everything a later run needs to relocalise
// into it and continue — the calibration, the estimator's state (gravity direction in W, biases), the
// trajectory, the relocalisation keyframes and every surfel, active and inactive — written atomically.
//
// Two ways, one encoding:
//  - saveMap streams the surfels from the GPU through the export's staging buffer into the file's write
//    buffer: one chunk on the host whatever the map's size, but the calling thread (the one that owns the Slam)
//    is blocked for the readback and the whole write. For the end of a run.
//  - captureMap copies the map into a MapSnapshot on the Slam's thread (the readback and a copy of the
//    keyframes), and writeMapFile writes that snapshot on any other thread while the Slam goes on: the SLAM
//    thread is held for the readback only (tests/bench has both costs). A snapshot reserved for the map's
//    capacity takes no allocation per capture. For a service that saves while it maps.
//
// The deformation graph is not saved: every closure builds a new one from the map (loop_closure.hpp), and the
// last one's only other use is moving this run's earlier poses, which the trajectory holds already moved.

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "vifusion/core/rig_calibration.hpp"
#include "vifusion/core/state.hpp"
#include "vifusion/mapfile/map_sections.hpp"
#include "vifusion/slam/slam.hpp"

namespace vifusion::slam {

struct MapSaveInputs {
  SlamMode mode = SlamMode::kRgbd;
  const RigCalibration* calibration = nullptr;       ///< the rig the Slam was built with
  std::span<const mapfile::StampedPose> trajectory;  ///< every located frame's pose so far, in order
  std::optional<NavState> state;                     ///< the estimator's last state (inertial modes)
};

struct MapSaveReport {
  std::uint64_t bytes = 0;    ///< the file's size
  std::uint32_t surfels = 0;  ///< surfels saved
  int keyframes = 0;          ///< relocalisation keyframes saved
  double elapsed_ms = 0.0;    ///< wall time of the write: readback (saveMap only), encoding, sync, rename
};

/// A host copy of everything a map file holds, taken between frames (captureMap).
struct MapSnapshot {
  SlamMode mode = SlamMode::kRgbd;
  RigCalibration calibration;
  std::vector<mapfile::StampedPose> trajectory;
  std::optional<NavState> state;
  std::optional<loop::FernDatabase> keyframes;  ///< nullopt: the Slam keeps none (relocalisation off)
  map::MapState map_state;
  std::uint32_t frame_clock = 0;     ///< Slam::frameClock() at the capture
  std::vector<map::Surfel> surfels;  ///< map_state.surfel_count of them
  double capture_ms = 0.0;           ///< wall time captureMap held its caller [ms]

  /// Reserves room for `surfels` surfels and `frames` poses, so that captures up to those sizes allocate
  /// nothing (a capture beyond them grows the vectors).
  void reserve(std::uint32_t surfel_capacity, std::size_t frames);
};

/// Writes the map to `path` (replacing it only when complete). @throws vifusion::Error naming the path and
/// the section on a failure; the file at `path` is then unchanged.
MapSaveReport saveMap(Slam& slam, const MapSaveInputs& inputs, const std::string& path);

/// Copies the map, keyframes and `inputs` into `snapshot`. Call between frames on the thread that owns `slam`.
void captureMap(Slam& slam, const MapSaveInputs& inputs, MapSnapshot& snapshot);

/// Writes a captured map to `path`, as saveMap would have written it then; any thread. @throws as saveMap.
MapSaveReport writeMapFile(const MapSnapshot& snapshot, const std::string& path);

}  // namespace vifusion::slam
