#pragma once
// The configuration of the service (vifusiond and vifusion-health read the same file,
// /etc/vifusion/vifusiond.yaml): plain option structs with defaults and validate(). Every field is
// a key of the YAML file and a command-line option (config_keys.hpp lists them).

#include <cstdint>
#include <string>

#include "vifusion/core/error.hpp"

namespace vifusion::config {

/// Exit codes of vifusiond and vifusion-health (README "Running the service").
/// Most passes `replay_loops` may ask for: a minute's recording replayed for about two years.
inline constexpr std::int64_t kMaxReplayLoops = 1'000'000;

inline constexpr int kExitOk = 0;
inline constexpr int kExitConfig = 2;  ///< bad configuration or command line
inline constexpr int kExitSource = 3;  ///< the source cannot be opened or read, or lacks the IMU data the mode needs
inline constexpr int kExitGpu = 4;  ///< no usable Vulkan device, the pipeline cannot be built, or the device was lost
inline constexpr int kExitDds = 5;  ///< the DDS participant, writers or readers cannot be created
inline constexpr int kExitOutput = 6;  ///< trajectory.txt, map.ply or the map file cannot be written
inline constexpr int kExitLed = 7;     ///< vifusion-health: the status LED's GPIO line is unavailable
inline constexpr int kExitMap = 8;     ///< vifusiond: map_file cannot be loaded and map_file_required is true

/// A configuration problem; the message names the key and, for a file, "file:line:".
class ConfigError : public Error {
 public:
  using Error::Error;
};

struct DdsConfig {
  std::uint32_t domain = 0;                             ///< DDS domain id, 0..232
  std::string config = "/etc/vifusion/cyclonedds.xml";  ///< Cyclone XML: a file, file:// URI or inline '<…>'
  std::string partition;                                ///< "" = the default partition (what ROS 2 uses)
  std::string world_frame = "map";                      ///< frame_id of the map world W
  /// frame_id of the odometry frame O (REP-105): odom → camera is continuous, map → odom jumps at a loop closure
  std::string odom_frame = "odom";
  std::string camera_frame = "camera";  ///< frame_id of the camera C
};

/// Thresholds of vifusion-health's rules (one diagnostic status per rule).
struct HealthConfig {
  double period_s = 0.25;          ///< rules are judged and rt/diagnostics published this often [s]
  double heartbeat_stale_s = 1.0;  ///< no status message for longer: STALE [s]
  double min_frame_rate_hz = 5.0;  ///< processed frame rate below this: WARN; zero while running: ERROR [Hz]
  double lost_error_s = 2.0;       ///< tracking lost for longer: ERROR (shorter: WARN) [s]
  std::string led_chip;            ///< status LED's gpiochip ("gpiochip0" or a path); "" = no LED
  std::int64_t led_line = 0;       ///< line offset of the LED on led_chip; lit while every rule is OK
};

/// The sync line (drivers/gpio_sync): the camera's strobe or an external trigger on a GPIO line, whose
/// kernel-stamped edges vifusiond reads and counts (`vifusion status` shows their rate).
struct SyncConfig {
  std::string chip;              ///< gpiochip name ("gpiochip0") or path; "" = no sync line
  std::int64_t line = 0;         ///< line offset on the chip, [0, 65535]
  std::string edges = "rising";  ///< rising, falling or both
};

/// map_capacity's default: map::kDefaultMapCapacity (map/surfel.hpp, the largest surfel array every Vulkan
/// device binds), restated here because this library is GPU-free; vifusiond asserts that the two agree.
inline constexpr std::int64_t kDefaultMapCapacity = 2'796'202;

struct DaemonConfig {
  std::string source =
      "sim:living_room_0";  ///< sim:NAME, dataset:DIR, tum:DIR, icl:DIR, 7scenes:DIR, klg:FILE, zr300[:SERIAL]
  std::string calibration;  ///< zr300 source: the rig's calibration.yaml (drivers/zr300 open_zr300.hpp)
  std::string out = "/var/lib/vifusion";  ///< state directory: trajectory.txt, map.ply, generated sim data
  std::string mode = "rgbd";              ///< rgbd, rgbdi (camera + IMU) or gyro (camera + gyroscope)
  std::int64_t max_frames = 0;            ///< stop cleanly after this many processed frames; 0: the whole source
  bool realtime = true;                   ///< replay a dataset at its timestamps (false: as fast as possible)
  std::string device;                     ///< GPU name filter ("" = best device)
  std::int64_t frame_ring = 4;            ///< camera ring capacity [frames], preallocated
  /// Surfels the map holds: its GPU memory, fixed at start (≈ 110 bytes a surfel). When it fills,
  /// the oldest inactive surfels make room (map_maintenance.hpp).
  std::int64_t map_capacity = kDefaultMapCapacity;
  double map_publish_period_s = 5.0;  ///< rt/vifusion/map every this many seconds; 0: never
  double status_period_s = 0.2;       ///< rt/vifusion/status every this many seconds (≥ 1 Hz)
  /// The robot's map across runs (slam/map_saving.hpp, README "Saving and loading a map"): loaded at start (the
  /// service relocalises into it; W is its frame) and saved to the same path on stop, every map_save_period_s
  /// and on request (rt/vifusion/map_save_request). "" = no map file: every start begins an empty map.
  std::string map_file;
  /// true: a map_file that is missing or refused (damaged, another camera, …) stops the start (exit code
  /// kExitMap) — a robot must not silently begin a new world frame. false: the service starts with an empty map;
  /// a refused file is first renamed to "<map_file>.refused" so that nothing saved is lost.
  bool map_file_required = true;
  /// Save the map file every this many seconds while running [s]; 0: only on stop and on request. Each save
  /// holds the SLAM thread for the map's readback only; the write happens on its own thread.
  double map_save_period_s = 300.0;
  /// false: localisation only (slam::SlamOptions::mapping), the mode a fleet robot runs in day to day: track against
  /// map_file without changing it; nothing is saved. Needs map_file with map_file_required: true.
  bool mapping = true;
  std::string log_file;  ///< log file, reopened on SIGHUP; "" = stderr (the journal)
  /// Record the source while mapping (drivers/recording: MCAP of ROS 2 messages) into record_dir.
  bool record = false;
  std::string record_dir;  ///< where recordings go ("" = <out>/recordings), one file per start
  /// Faults replayed into a recorded source, NAME@FRAME[:VALUE],… (datasets/fault_injection.hpp); "" = none.
  std::string inject;
  /// A recorded source replayed this many times end to end as one long source (datasets/looped_replay.hpp; soak
  /// runs), [1, kMaxReplayLoops]; 1: once.
  std::int64_t replay_loops = 1;
  DdsConfig dds;
  HealthConfig health;
  SyncConfig sync;

  /// Throws ConfigError naming the first key whose value is out of range.
  void validate() const;
};

}  // namespace vifusion::config
