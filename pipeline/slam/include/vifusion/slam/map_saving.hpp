#pragma once
// Saving the running map to a map file (mapfile/map_sections.hpp): everything a later run needs to relocalise
// into it and continue — the calibration, the estimator's state (gravity direction in W, biases), the
// trajectory, the relocalisation keyframes and every surfel, active and inactive — written atomically.
//
// The surfels stream from the GPU through the export's staging buffer (Slam::visitMap) into the file's write
// buffer, so saving holds one chunk on the host whatever the map's size. Call between frames on the thread
// that owns the Slam; it blocks that thread for the readback and the write (tests/bench has the cost).
//
// The deformation graph is not saved: every closure builds a new one from the map (loop_closure.hpp), and the
// last one's only other use is moving this run's earlier poses, which the trajectory holds already moved.

#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "vifusion/core/rig_calibration.hpp"
#include "vifusion/core/state.hpp"
#include "vifusion/mapfile/map_sections.hpp"
#include "vifusion/slam/slam.hpp"

namespace vifusion::slam {

struct MapSaveInputs {
  SlamMode mode = SlamMode::kRgbd;
  const RigCalibration* calibration = nullptr;       ///< the rig the Slam was built with
  std::span<const mapfile::StampedPose> trajectory;  ///< every frame's pose so far, in order
  std::optional<NavState> state;                     ///< the estimator's last state (inertial modes)
};

struct MapSaveReport {
  std::uint64_t bytes = 0;    ///< the file's size
  std::uint32_t surfels = 0;  ///< surfels saved
  int keyframes = 0;          ///< relocalisation keyframes saved
  double elapsed_ms = 0.0;    ///< wall time of the whole save: readback, write, sync, rename
};

/// Writes the map to `path` (replacing it only when complete). @throws vifusion::Error naming the path and
/// the section on a failure; the file at `path` is then unchanged.
MapSaveReport saveMap(Slam& slam, const MapSaveInputs& inputs, const std::string& path);

}  // namespace vifusion::slam
