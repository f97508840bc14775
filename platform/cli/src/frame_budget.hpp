#pragma once
// Where a run's frame time went: the mean per frame of every stage slam::Slam measures — preprocessing,
// tracking and mapping as host wall time, the map update's stages as GPU time from device timestamps
// (slam::MapStageTimes; absent on devices without timestamps), loop closure and relocalisation inside
// mapping — and the GPU stages ranked by their share, for report.json's "ms_per_frame" and "gpu_stages".

#include <nlohmann/json.hpp>

#include "vifusion/slam/slam.hpp"

namespace vifusion::cli {

class FrameBudget {
 public:
  void add(const slam::FrameResult& result);
  /// {"preprocess", "tracking", "mapping", "closure", "total"}: means over every frame [ms].
  nlohmann::json wallJson() const;
  /// {"fusion", "maintenance", "prediction", "reference"}: means over the frames that measured them [ms], and
  /// "ranking": the stage names from the largest mean down; null when the device has no timestamps.
  nlohmann::json gpuJson() const;

 private:
  /// Sum and count of one stage's measured frames.
  struct Stage {
    double sum_ms = 0.0;
    int frames = 0;
    void add(double ms) {
      if (ms < 0.0) return;  // not measured this frame
      sum_ms += ms;
      ++frames;
    }
    double mean() const { return frames > 0 ? sum_ms / frames : 0.0; }
  };
  int frames_ = 0;
  Stage preprocess_, tracking_, mapping_, closure_;
  Stage fusion_, maintenance_, prediction_, reference_;
};

}  // namespace vifusion::cli
