#pragma once
// A timestamped rigid pose, the unit of a trajectory file. Field names match vifusion::eval::StampedPose
// so a caller that reads TUM files converts with a plain loop; drivers may not depend on eval.

#include <cstdint>

#include "vifusion/core/se3.hpp"

namespace vifusion::sim {

struct StampedPose {
  std::int64_t t_ns = 0;  ///< stamp [ns]
  SE3d T_world_body;      ///< body → world (for camera paths: T_W_C)
};

}  // namespace vifusion::sim
