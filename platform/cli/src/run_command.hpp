#pragma once
// `vifusion run`: the main job. Opens a source (a dataset spec, `sim:NAME`, which generates the
// synthetic sequence first, or the live camera `zr300[:SERIAL]`, which runs until --frames or Ctrl-C), runs the
// pipeline on every frame and writes trajectory.txt (TUM), map.ply and report.json into the output directory, and in
// the inertial modes states.csv (eval/state_csv.hpp); with --save-map also the map file.

#include <cstdint>
#include <memory>
#include <string>

#include "vifusion/map/surfel.hpp"

namespace vifusion::zr300 {
class Zr300Backend;
}

namespace vifusion::cli {

struct RunOptions {
  std::string source =
      "sim:living_room_0";           ///< sim:NAME, tum:DIR, icl:DIR, 7scenes:DIR, klg:FILE, dataset:DIR, zr300[:SERIAL]
  std::string calibration;           ///< zr300: the rig's calibration.yaml (open_zr300.hpp)
  std::string mode = "rgbd";         ///< rgbd, rgbdi (with the IMU) or gyro (gyroscope only)
  std::string out = "vifusion_out";  ///< output directory
  std::string device;                ///< GPU name filter
  int max_frames = 0;                ///< > 0: stop after this many frames
  bool photometric = true;           ///< use the photometric term besides ICP
  std::uint32_t map_capacity = map::MapOptions{}.capacity;  ///< surfels the map holds (fixed memory)
  bool loop_closure = true;    ///< local loop closure by map deformation (off: the paper's open-loop odometry)
  bool relocalisation = true;  ///< relocalise a lost camera by place recognition (slam/relocaliser.hpp)
  bool gravity_term = true;    ///< the paper's E_imu in the deformation energy (inertial modes; the ablation when off)
  std::string load_map;        ///< non-empty: start from this saved map (slam/map_loading.hpp)
  std::string save_map;        ///< non-empty: save the map to this file at the end (slam/map_saving.hpp)
  bool localisation_only = false;  ///< track against load_map without changing it (SlamOptions::mapping false)
  /// A recorded frame or IMU row that cannot be read stops the run (outputs written, exit 3) instead of being
  /// skipped.
  bool strict = false;
  /// Faults injected into a recorded source (datasets/fault_injection.hpp's NAME@FRAME[:VALUE] list; empty: none).
  std::string inject;
};

/// Returns the exit code: 0, or 3 when the live camera cannot be opened (the message on stderr names what is
/// missing) or, with `strict`, after a recorded frame could not be read (the outputs hold the frames before it), or 4
/// when the GPU pipeline fails mid-run (the device lost): trajectory, states, frames and report hold every frame
/// before it, and the map too where it can still be read back (report.json `stopped_by_pipeline_failure`).
/// Without `strict` such frames and rows are skipped and counted (report.json `skipped_frames`,
/// `skipped_imu_rows`), as is a frame whose time does not increase. `backend` reaches the camera
/// for `zr300` sources; null: the real devices (tests pass a scripted camera). @throws vifusion::Error for every other
/// failure (main() reports it, exit code 2).
int runPipeline(const RunOptions& options, std::unique_ptr<zr300::Zr300Backend> backend);
/// The same on the real devices.
int runPipeline(const RunOptions& options);

}  // namespace vifusion::cli
