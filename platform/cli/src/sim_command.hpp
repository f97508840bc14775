#pragma once
// `vifusion sim`: the synthetic RGB-D-inertial benchmark, reproducing the paper's recipe. A camera
// path (an ICL-NUIM living-room trajectory, a synthetic preset or any TUM file) is fitted with a
// smooth spline through every 10th pose (--fit-stride), refused when it cannot follow them; the spline is the ground
// truth from which the IMU is simulated (Table I noise) and the procedural living room is rendered with ICL-NUIM-style
// noise.

#include <cstdint>
#include <string>

namespace vifusion::cli {

struct SimOptions {
  std::string preset;             ///< living_room_0..3, fast, quick_rotation, white_wall, long
  std::string trajectory;         ///< or any TUM pose file (T_world_camera)
  std::string up = "y";           ///< up axis of the trajectory's world (gravity along −up)
  std::string imu = "synthetic";  ///< IMU noise preset: synthetic or zr300 (Table I columns)
  std::string out;                ///< dataset directory to create
  std::string data_dir;  ///< where icl-nuim-trajectories/ lives (default: $VIFUSION_DATA_DIR or ../shared/data)
  uint64_t seed = 1;     ///< same seed, same dataset
  int width = 640;       ///< image size [px]; intrinsics scale with it
  int height = 480;
  /// The spline goes through every fit_stride-th pose; 0: the preset's (sim::PresetTraits), else 10. A fit that
  /// misses its own samples beyond sim::FitTolerance is refused, naming the worst pose.
  int fit_stride = 0;
  double duration_s = 0.0;  ///< > 0: only the first duration_s seconds
  /// A covered camera (a hand over the lens): frames from cover_start_s for cover_s seconds after the first
  /// frame are black with no depth, the IMU and the ground truth go on. cover_s 0: never covered.
  double cover_start_s = 0.0;
  double cover_s = 0.0;
  int motion_blur_samples = -1;  ///< sub-frame renders per image; −1: 5 for fast presets, else none
  bool noise = true;             ///< sensor noise on images and IMU white noise
  bool biases = true;            ///< IMU biases (initial, random walk, static)
  bool quiet = false;            ///< no summary line on stdout (when another command generates the data)
};

/// Writes the dataset and prints one JSON line describing it; returns the exit code.
int runSim(const SimOptions& options);

}  // namespace vifusion::cli
