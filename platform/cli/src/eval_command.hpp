#pragma once
// `vifusion eval`: trajectory, state and map errors of one run against ground truth, as one JSON
// line on stdout plus optional PNG plots.

#include <string>

namespace vifusion::cli {

struct EvalOptions {
  std::string gt;   ///< TUM ground-truth trajectory (T_world_camera)
  std::string est;  ///< TUM estimated trajectory
  /// TUM ground truth of the run whose first camera is the estimate's W (a run that relocalised into a map
  /// saved by that run): adds the ATE in that frame, without alignment (optional)
  std::string gt_origin;
  std::string states;              ///< estimator states.csv (optional)
  std::string gt_states;           ///< groundtruth_states.csv (default: beside --gt)
  std::string map;                 ///< map PLY to score against the simulator's living room (optional)
  std::string plots_dir;           ///< where to write PNG plots (optional)
  std::string up = "y";            ///< up axis of the ground truth's world: gravity along −up
  double max_difference_s = 0.02;  ///< ATE stamp association window [s]
  double rpe_delta_s = 1.0;        ///< RPE step [s]
};

/// Prints the JSON line; returns the exit code. Throws vifusion::Error on bad input.
int runEval(const EvalOptions& options);

}  // namespace vifusion::cli
