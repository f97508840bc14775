#pragma once
// bench_rgbd_slam's command line (its own flags; Google Benchmark's --benchmark_* come on top), the
// sequence it runs on and the GPU context every entry shares.

#include <string>
#include <vector>

#include "vifusion/gpu/gpu_context.hpp"

namespace vifusion::bench {

constexpr const char* kPreset = "living_room_0";
constexpr double kFrameRateHz = 30.0;  // `vifusion sim` renders at 30 Hz

struct Size {
  int width = 0;
  int height = 0;
  std::string name() const { return std::to_string(width) + "x" + std::to_string(height); }
};

/// Command-line options of this benchmark (Google Benchmark's own --benchmark_* flags come on top).
struct BenchOptions {
  int frames = 90;  ///< frames per sequence, the first one untimed
  std::vector<Size> sizes = {{640, 480}, {320, 240}};
  std::string data_dir = VIFUSION_BENCH_DATA_DIR;  ///< where the generated sequences are kept
  std::string vifusion = VIFUSION_BENCH_CLI;       ///< the `vifusion` program that generates them
  bool noise = true;                               ///< ICL-NUIM-style sensor noise (sim's default); 0: --no-noise
  bool photometric = true;                         ///< TrackerOptions::use_photometric (0: ICP only)
  bool opencv = true;                              ///< run cv::rgbd::RgbdICPOdometry for comparison
  bool open3d = true;                              ///< run Open3D's tensor dense SLAM for comparison
  std::string mode = "rgbd";                       ///< slam::SlamMode by name: rgbd, or rgbdi (with the IMU)
  bool steps = true;                               ///< register the per-step entries
  std::string trajectory_dir;                      ///< non-empty: write the estimated trajectories (TUM) here
};

/// The options in force (defaults until parseOptions).
BenchOptions& options();

/// Takes this benchmark's flags out of argv (Google Benchmark rejects flags it does not know);
/// throws Error naming the flag on a bad value.
void parseOptions(int& argc, char** argv);

/// When `arg` is "NAME=VALUE" for this `name`, sets `value` and returns true (for a benchmark's own flags).
bool takeFlag(const char* arg, const char* name, std::string& value);
/// "1"/"true" or "0"/"false"; throws Error naming `flag` otherwise.
bool parseBoolFlag(const std::string& flag, const std::string& value);
/// An integer in [min, max]; throws Error naming `flag` otherwise.
int parseIntFlag(const std::string& flag, const std::string& value, int min, int max);

/// The Vulkan device of every entry (picked once, honouring the VIFUSION_GPU_* environment).
gpu::GpuContext& context();

}  // namespace vifusion::bench
