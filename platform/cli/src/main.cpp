// vifusion: command-line front end. Subcommands grow with the issues; every one prints its
// options with defaults under --help and exits non-zero with a message on bad input.

#include <CLI/CLI.hpp>
#include <cstdio>

#include "calib_command.hpp"
#include "eval_command.hpp"
#include "gpu_self_check.hpp"
#include "map_command.hpp"
#include "record_command.hpp"
#include "run_command.hpp"
#include "service_commands.hpp"
#include "sim_command.hpp"
#include "synccheck_command.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/core/version.hpp"

int main(int argc, char** argv) {
  CLI::App app{"vifusion: dense RGB-D-inertial SLAM on Vulkan compute"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("vifusion ") + vifusion::versionString());

  vifusion::cli::SelfCheckOptions self_check;
  CLI::App* self_check_command =
      app.add_subcommand("selfcheck",
                         "GPU self-check: preprocessing kernels and reduction on a built-in frame, checked against the "
                         "CPU references, with timings");
  self_check_command->add_option("--device", self_check.device,
                                 "GPU name filter (default: best device; env VIFUSION_GPU_DEVICE)");
  self_check_command->add_option("--width", self_check.width, "Frame width [px], even")
      ->capture_default_str()
      ->check(CLI::Range(16, 4096));
  self_check_command->add_option("--height", self_check.height, "Frame height [px]")
      ->capture_default_str()
      ->check(CLI::Range(16, 4096));
  self_check_command->add_option("--frames", self_check.frames, "Timed repetitions per step")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));

  vifusion::cli::RunOptions run_options;
  CLI::App* run = app.add_subcommand(
      "run",
      "Run the pipeline on a source and write trajectory.txt and report.json (default: the synthetic "
      "living-room sequence, generated on first use)");
  run->add_option("--source", run_options.source,
                  "sim:NAME, tum:DIR, icl:DIR, 7scenes:DIR, klg:FILE, dataset:DIR, rec:FILE.mcap, or the live camera "
                  "zr300[:SERIAL]")
      ->capture_default_str();
  run->add_option(
      "--calibration", run_options.calibration,
      "The rig's calibration.yaml (Kalibr cam0, cam1, imu0 keys; depth_noise and inverse_depth_bias_per_m from "
      "`calib noise --out`). zr300: its image size picks the stream preset; a recorded source is read with it in "
      "place of its own");
  run->add_option("--mode", run_options.mode, "rgbd, rgbdi (tightly coupled IMU) or gyro (gyroscope only)")
      ->capture_default_str();
  run->add_option("--out", run_options.out, "Output directory")->capture_default_str();
  run->add_option("--device", run_options.device, "GPU name filter (default: best device; env VIFUSION_GPU_DEVICE)");
  run->add_option("--frames", run_options.max_frames, "Stop after this many frames (0: all)")->capture_default_str();
  run->add_flag("--strict", run_options.strict,
                "Stop at the first recorded frame or IMU row that cannot be read (outputs written, exit 3) instead of "
                "skipping and counting it");
  run->add_option(
      "--inject", run_options.inject,
      "Replay a recorded source with faults, e.g. imu-gap@40,frame-duplicate@60,clock-jump@80:+1,"
      "device-lost@120 (NAME@FRAME[:VALUE]; README \"Bad input and faults\" lists them and their outcomes)");
  run->add_flag("!--no-photometric", run_options.photometric, "Track with ICP only");
  run->add_flag("!--no-loop-closure", run_options.loop_closure, "Open-loop odometry: no map deformation");
  run->add_flag("!--no-relocalisation", run_options.relocalisation,
                "A lost camera recovers only from its last pose and motion, not by recognising a place");
  run->add_flag("!--no-gravity-term", run_options.gravity_term,
                "Deform without the gravity term E_imu (the ablation; inertial modes)");
  run->add_option("--map-capacity", run_options.map_capacity,
                  "Surfels the map holds (fixed GPU memory, about 110 bytes a surfel: report.json arena_bytes)")
      ->capture_default_str()
      ->check(CLI::Range(1u << 16, 1u << 26));
  run->add_option("--load-map", run_options.load_map,
                  "Start from this saved map: relocalise into it (nothing is fused until then), then track and map in "
                  "its frame");
  run->add_flag("--localisation-only", run_options.localisation_only,
                "Track against the --load-map map without changing it: nothing fused, no closure, no keyframe (the "
                "mode a fleet robot runs in day to day)");
  run->add_option("--save-map", run_options.save_map,
                  "Save the map at the end of the run to this file (surfels, keyframes, trajectory, calibration, "
                  "estimator state; `vifusion map info FILE` checks it)");

  vifusion::cli::EvalOptions eval;
  CLI::App* eval_command = app.add_subcommand(
      "eval", "Evaluate a run against ground truth: ATE, RPE, velocity/bias/gravity errors; one JSON line on stdout");
  eval_command->add_option("--gt", eval.gt, "Ground-truth trajectory (TUM format, T_world_camera)")->required();
  eval_command->add_option("--est", eval.est, "Estimated trajectory (TUM format)")->required();
  eval_command->add_option("--gt-origin", eval.gt_origin,
                           "Ground truth of the run that saved the map this run loaded: adds the ATE in its frame "
                           "(W = its first camera), without alignment");
  eval_command->add_option("--states", eval.states, "Estimator states.csv: adds velocity, bias and gravity errors");
  eval_command->add_option("--gt-states", eval.gt_states,
                           "Ground-truth states (default: groundtruth_states.csv beside --gt)");
  eval_command->add_option("--map", eval.map, "Map PLY: mean distance to the simulator's living room surfaces");
  eval_command->add_option("--plots", eval.plots_dir, "Directory for PNG plots");
  eval_command->add_option("--up", eval.up, "Up axis of the ground truth's world (gravity along -up)")
      ->capture_default_str()
      ->check(CLI::IsMember({"y", "z"}));
  eval_command->add_option("--max-difference", eval.max_difference_s, "ATE association window [s]")
      ->capture_default_str();
  eval_command->add_option("--rpe-delta", eval.rpe_delta_s, "RPE step [s]")->capture_default_str();

  vifusion::cli::SimOptions sim;
  CLI::App* sim_command = app.add_subcommand(
      "sim", "Write a synthetic RGB-D-inertial dataset: spline ground truth, simulated IMU, rendered living room");
  sim_command->add_option(
      "--preset", sim.preset,
      "living_room_0..3, fast, quick_rotation, white_wall, long, unmapped_turn, fast_pan or revisit");
  sim_command->add_option("--trajectory", sim.trajectory, "Camera path as a TUM pose file (T_world_camera)");
  sim_command->add_option("--out", sim.out, "Dataset directory to create, or a recording FILE.mcap")->required();
  sim_command->add_option("--seed", sim.seed, "Random seed: same seed, same dataset")->capture_default_str();
  sim_command->add_option("--imu", sim.imu, "IMU noise (Table I column)")
      ->capture_default_str()
      ->check(CLI::IsMember({"synthetic", "zr300"}));
  sim_command->add_option("--up", sim.up, "Up axis of the trajectory's world")
      ->capture_default_str()
      ->check(CLI::IsMember({"y", "z"}));
  sim_command->add_option("--width", sim.width, "Image width [px], even")
      ->capture_default_str()
      ->check(CLI::Range(16, 4096));
  sim_command->add_option("--height", sim.height, "Image height [px]")
      ->capture_default_str()
      ->check(CLI::Range(16, 4096));
  sim_command
      ->add_option("--fit-stride", sim.fit_stride,
                   "Fit the ground-truth spline through every n-th pose (default: the preset's, else 10 as the paper); "
                   "smaller follows faster motion")
      ->check(CLI::Range(1, 1000));
  sim_command->add_option("--duration", sim.duration_s, "Only the first seconds (0: whole path)")
      ->capture_default_str();
  sim_command
      ->add_option_function<std::vector<double>>(
          "--cover",
          [&sim](const std::vector<double>& v) {
            sim.cover_start_s = v.at(0);
            sim.cover_s = v.at(1);
          },
          "Covered camera: START SECONDS after the first frame, frames black with no depth (IMU goes on)")
      ->expected(2);
  sim_command
      ->add_option("--motion-blur", sim.motion_blur_samples,
                   "Sub-frame renders per image (-1: 5 for fast presets, else 1)")
      ->capture_default_str();
  sim_command->add_option("--data-dir", sim.data_dir,
                          "Folder holding icl-nuim-trajectories/ (default: VIFUSION_DATA_DIR)");
  sim_command->add_flag("!--no-noise", sim.noise, "No image noise and no IMU white noise");
  sim_command->add_flag("!--no-biases", sim.biases, "No IMU biases");

  const auto add_dds_options = [](CLI::App* command, vifusion::cli::DdsSelection& dds) {
    command->add_option("--config", dds.config_file,
                        "vifusiond YAML whose dds.* keys to use (default: /etc/vifusion/vifusiond.yaml if present)");
    command->add_option("--dds-config", dds.dds_config, "Cyclone DDS XML (file, file:// URI or inline)");
    command->add_option("--domain", dds.domain, "DDS domain id (default: the config's dds.domain)")
        ->check(CLI::Range(0, 232));
    command->add_option("--partition", dds.partition, "DDS partition (default: the config's dds.partition)");
  };
  vifusion::cli::EchoCommandOptions echo;
  CLI::App* echo_command =
      app.add_subcommand("echo", "Print the samples of one of vifusion's DDS topics as JSON lines");
  echo_command
      ->add_option("topic", echo.topic, "rt/vifusion/odometry or /vifusion/odometry, rt/tf, rt/diagnostics, ...")
      ->required();
  echo_command->add_option("--count", echo.count, "Stop after this many samples (0: no limit)")->capture_default_str();
  echo_command->add_option("--timeout", echo.timeout_s, "Give up after this many seconds (0: never)")
      ->capture_default_str();
  echo_command->add_flag("--full-arrays", echo.full_arrays, "Print byte arrays (PointCloud2 data) in full");
  add_dds_options(echo_command, echo.dds);

  vifusion::cli::RecordOptions record;
  CLI::App* record_command = app.add_subcommand(
      "record",
      "Record a source (the live camera with IMU, clocks and sync line, or any recorded source) into an MCAP file "
      "of ROS 2 messages; or --recover a recording that was cut short");
  record_command->add_option("--source", record.source, "zr300[:SERIAL] or any source of `vifusion run`")
      ->capture_default_str();
  record_command->add_option("--calibration", record.calibration,
                             "The rig's calibration.yaml (zr300; a recorded source: in place of its own)");
  record_command->add_option("--mode", record.mode, "rgbd records no IMU; rgbdi and gyro record it")
      ->capture_default_str()
      ->check(CLI::IsMember({"rgbd", "rgbdi", "gyro"}));
  record_command->add_option("--out", record.out, "The recording to create, FILE.mcap (with --recover: the output)");
  record_command->add_option("--duration", record.duration_s, "Stop after this many seconds of source time (0: never)")
      ->capture_default_str();
  record_command->add_flag("--realtime", record.realtime, "Recorded sources: deliver frames at their timestamps");
  record_command->add_option("--gpio", record.gpio, "Record the sync line CHIP:LINE (e.g. gpiochip0:17)");
  record_command->add_option("--edges", record.edges, "The sync line's edges")
      ->capture_default_str()
      ->check(CLI::IsMember({"rising", "falling", "both"}));
  record_command->add_option("--recover", record.recover,
                             "Rewrite this cut recording complete (into --out, default FILE.recovered.mcap)");

  vifusion::cli::SyncCheckCommandOptions sync;
  CLI::App* synccheck_command = app.add_subcommand(
      "synccheck",
      "Check that camera, IMU and sync-line timestamps agree: offsets, jitter, drift, drops; JSON on stdout, "
      "exit code 1 when a check fails");
  synccheck_command->add_option("--source", sync.source, "zr300[:SERIAL] (live) or rec:FILE.mcap")
      ->capture_default_str();
  synccheck_command->add_option("--calibration", sync.calibration,
                                "The rig's calibration.yaml (zr300; a recorded source: in place of its own)");
  synccheck_command->add_option("--gpio", sync.gpio, "Live: the sync line CHIP:LINE");
  std::string polarity = "rising";
  synccheck_command->add_option("--edges", polarity, "The edge of each strobe pulse")
      ->capture_default_str()
      ->check(CLI::IsMember({"rising", "falling"}));
  synccheck_command->add_option("--duration", sync.duration_s, "Live: seconds to collect")->capture_default_str();
  synccheck_command->add_flag("--simulate", sync.simulate, "Analyse a simulated clock model instead of a source");
  synccheck_command->add_option("--sim-offset-ns", sync.model.offset_ns, "Simulated frame − strobe offset [ns]")
      ->capture_default_str();
  synccheck_command->add_option("--sim-drift-ppm", sync.model.drift_ppm, "Simulated drift [ppm]")
      ->capture_default_str();
  synccheck_command->add_option("--sim-jitter-ns", sync.model.jitter_ns, "Simulated jitter std [ns]")
      ->capture_default_str();
  synccheck_command->add_option("--sim-drop", sync.model.drop_probability, "Simulated dropped-frame probability")
      ->capture_default_str();
  synccheck_command->add_option("--sim-duration", sync.model.duration_s, "Simulated seconds")->capture_default_str();
  synccheck_command->add_option("--seed", sync.seed, "Simulation seed")->capture_default_str();
  synccheck_command->add_option("--max-offset-ns", sync.check.max_abs_offset_ns, "Limit on |median offset| [ns]")
      ->capture_default_str();
  synccheck_command->add_option("--max-jitter-ns", sync.check.max_jitter_p99_ns, "Limit on jitter p99 [ns]")
      ->capture_default_str();
  synccheck_command->add_option("--max-drift-ppm", sync.check.max_abs_drift_ppm, "Limit on |drift| [ppm]")
      ->capture_default_str();
  synccheck_command->add_option("--max-dropped", sync.check.max_dropped_fraction, "Limit on dropped frames (fraction)")
      ->capture_default_str();
  synccheck_command->add_option("--max-imu-gap-ns", sync.check.max_imu_gap_ns, "Limit on the largest IMU gap [ns]")
      ->capture_default_str();
  synccheck_command->add_option("--plot", sync.plot, "Write a PNG of the offsets over time");

  vifusion::cli::StatusCommandOptions status;
  CLI::App* status_command = app.add_subcommand(
      "status", "Read rt/vifusion/status and rt/diagnostics once and print the service's state and health verdict");
  status_command->add_option("--timeout", status.timeout_s, "Wait at most this many seconds")->capture_default_str();
  add_dds_options(status_command, status.dds);

  CLI::App* map_command = app.add_subcommand("map", "Map files (vifusion run --save-map)");
  map_command->require_subcommand(1);
  std::string map_file;
  CLI::App* map_info_command = map_command->add_subcommand(
      "info",
      "Check a map file (every section's checksum, sizes and values) and print what it holds as JSON; exit 2 "
      "naming the damaged section");
  map_info_command->add_option("file", map_file, "The map file")->required();
  vifusion::cli::MapSaveCommandOptions map_save;
  CLI::App* map_save_command = map_command->add_subcommand(
      "save",
      "Ask the running vifusiond to save its map file now (over DDS: rt/vifusion/map_save_request, answered in "
      "rt/vifusion/status); exit 0 once saved");
  map_save_command->add_option("--timeout", map_save.timeout_s, "Wait at most this many seconds")
      ->capture_default_str();
  add_dds_options(map_save_command, map_save.dds);

  CLI::App* calib_command = app.add_subcommand("calib", "Calibrate the sensors from data");
  calib_command->require_subcommand(1);
  vifusion::cli::CalibNoiseOptions calib_noise;
  CLI::App* calib_noise_command = calib_command->add_subcommand(
      "noise",
      "Measure the camera's depth and intensity noise (σ, quantisation, spatial correlation) from frame pairs of a "
      "dataset with ground-truth poses; one JSON object on stdout");
  calib_noise_command
      ->add_option("--source", calib_noise.source, "Dataset with ground truth (dataset:DIR, 7scenes:DIR, …)")
      ->required();
  calib_noise_command->add_option("--frame-step", calib_noise.frame_step, "Frames between the two frames of a pair")
      ->capture_default_str();
  calib_noise_command->add_option("--max-pairs", calib_noise.max_pairs, "Frame pairs, spread over the sequence")
      ->capture_default_str();
  calib_noise_command->add_option("--focal-baseline", calib_noise.focal_baseline_px_m,
                                  "The sensor's f·b [px·m] (default: the calibration's depth_noise value)");
  calib_noise_command->add_option("--out", calib_noise.out,
                                  "Write the dataset's calibration.yaml with the measured noise here");

  CLI11_PARSE(app, argc, argv);
  try {
    if (self_check_command->parsed()) return vifusion::cli::runGpuSelfCheck(self_check);
    if (run->parsed()) return vifusion::cli::runPipeline(run_options);
    if (eval_command->parsed()) return vifusion::cli::runEval(eval);
    if (sim_command->parsed()) return vifusion::cli::runSim(sim);
    if (echo_command->parsed()) return vifusion::cli::runEcho(echo);
    if (status_command->parsed()) return vifusion::cli::runStatus(status);
    if (record_command->parsed()) return vifusion::cli::runRecord(record);
    if (calib_noise_command->parsed()) return vifusion::cli::runCalibNoise(calib_noise);
    if (map_info_command->parsed()) return vifusion::cli::runMapInfo(map_file);
    if (map_save_command->parsed()) return vifusion::cli::runMapSave(map_save);
    if (synccheck_command->parsed()) {
      sync.edges = polarity;
      sync.check.edge_polarity = *vifusion::synccheck::parseEdgePolarity(polarity);
      return vifusion::cli::runSyncCheck(sync);
    }
  } catch (const std::exception& error) {
    std::fprintf(stderr, "vifusion: %s\n", error.what());
    return 2;
  }
  return 0;
}
