#pragma once
// Starting from a saved map (slam/map_saving.hpp wrote it; Slam::loadMap reads it): the surfels go into the
// GPU's map chunk by chunk through the import's staging buffer as the file is read, the keyframes replace the
// relocaliser's, and the map's frame clock continues from the saved one, so the saved surfels age as they would
// have (those not updated within the time window are inactive: loop closure's to bring back).
//
// The run then starts relocalising: every frame is looked up among the saved keyframes and verified by
// tracking it against the map rendered at the keyframe's pose (Slam::relocalise, the test that ends a loss).
// Until one passes, nothing is fused, the pose is not a pose (FrameResult::relocalising), and the map stays as
// saved. Once located, the saved surfels in view are made active again (loop closure's reactivation: they have
// aged past the time window meanwhile), and W is the saved map's frame: tracking, fusion and loop closure continue in
// it, and in the inertial modes the estimator starts there with the saved gravity direction and biases.

#include <cstdint>
#include <optional>
#include <string>

#include "vifusion/core/state.hpp"

namespace vifusion::slam {

struct MapLoadReport {
  std::string mode;               ///< the mode that built the map
  std::uint64_t bytes = 0;        ///< the file's size
  std::uint32_t surfels = 0;      ///< surfels loaded
  int keyframes = 0;              ///< relocalisation keyframes loaded
  std::uint32_t frames = 0;       ///< frames of the run(s) that built it
  std::uint32_t first_frame = 0;  ///< the frame clock's value at this run's first frame
  std::optional<NavState> state;  ///< the estimator's state when it was saved (inertial modes)
  double elapsed_ms = 0.0;        ///< wall time of the whole load
};

}  // namespace vifusion::slam
