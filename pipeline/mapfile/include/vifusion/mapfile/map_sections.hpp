#pragma once
// What each section of a map file holds (map_file_format.hpp has the container), field by field in file order.
// Types: u8/u32/u64/i32/i64 little-endian integers, f32/f64 IEEE-754; str = u32 length + that many bytes;
// pose = f64 qx qy qz qw tx ty tz (T_W_C: camera → W, unit quaternion).
//
//   meta      str mode ("rgbd", "rgbdi", "gyro") | u32 frames (the map's frame clock: frames of every run that
//             built it; surfel times count these) | i64 first frame t_ns | i64 last frame t_ns
//   calib     colour camera: i32 width, i32 height, f64 fx fy cx cy | u8 depth camera present, then its camera
//             (as above) and pose T_C_D | f64 depth_scale_m | f64 inverse_depth_bias_per_m | pose T_S_C |
//             i64 time_shift_cam_imu_ns | IMU noise: f64 gyro_saturation accel_saturation gyro_noise_density
//             accel_noise_density gyro_bias_prior accel_bias_prior gyro_random_walk accel_random_walk
//             gravity_mps2 rate_hz, f64×3 static_accel_bias | f64×3 g_W
//   state     u8 present | NavState: f64×3 r_W_C, f64×4 q_W_C (xyzw), f64×3 v_I_S, f64×3 b_g, f64×3 b_a,
//             f64×4 q_I_W (xyzw: the gravity direction in W)
//   traj      u64 poses | per pose: i64 t_ns, pose
//   keyframe  u8 present (0: relocalisation was off, nothing follows) | fern options: i32 num_ferns, i32
//   downsample_factor, f32 min_depth_m, f32 max_depth_m,
//             f64 keyframe_threshold, f64 min_valid_fraction, i32 capacity, u64 seed | i32 input width, i32 input
//             height | u32 keyframes | per keyframe: pose, i64 t_ns, u32 frame index, u8×num_ferns codes,
//             u8×3·w·h colour, f32×w·h depth_m (w × h: the input size / downsample_factor)
//   surfels   u32 surfels | u32 active_begin (surfels before it are inactive) | u32 frame of the last fusion |
//             per surfel the 12 f32 of map/surfel.hpp's record, bit for bit (the colour is RGB8 bits in an f32)
//
// Decoders check every value they can (sizes, finiteness, the options' own validation) and name the section.

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "vifusion/core/rig_calibration.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/core/state.hpp"
#include "vifusion/loop/fern_database.hpp"
#include "vifusion/mapfile/map_file_reader.hpp"
#include "vifusion/mapfile/map_file_writer.hpp"

namespace vifusion::mapfile {

/// 32-bit words per surfel: map::Surfel is three vec4 (the GPU's std430 record).
inline constexpr std::size_t kSurfelFloats = 12;
/// Longest mode name accepted in `meta` [bytes]: a longer one is corruption, not a mode.
inline constexpr std::uint32_t kMaxModeNameBytes = 16;

struct MapMeta {
  std::string mode;             ///< the SLAM mode that built it (slam::slamModeName)
  std::uint32_t frames = 0;     ///< the frame clock: frames of every run that built the map
  std::int64_t first_t_ns = 0;  ///< the first frame's time [ns]
  std::int64_t last_t_ns = 0;   ///< the last frame's time [ns]
  bool operator==(const MapMeta&) const = default;
};

struct StampedPose {
  std::int64_t t_ns = 0;
  SE3d T_W_C;
};

/// The map's surfel array: its counts, then surfel_count records follow in the section.
struct SurfelsHeader {
  std::uint32_t surfel_count = 0;
  std::uint32_t active_begin = 0;  ///< surfels [0, active_begin) are inactive
  std::uint32_t frame = 0;         ///< the frame last fused
  bool operator==(const SurfelsHeader&) const = default;
};

void writeMeta(MapFileWriter& writer, const MapMeta& meta);
MapMeta readMeta(MapFileReader& reader);

void writeCalibration(MapFileWriter& writer, const RigCalibration& calibration);
RigCalibration readCalibration(MapFileReader& reader);

/// `state`: the estimator's last state (inertial modes), nullopt in rgbd mode.
void writeState(MapFileWriter& writer, const std::optional<NavState>& state);
std::optional<NavState> readState(MapFileReader& reader);

void writeTrajectory(MapFileWriter& writer, std::span<const StampedPose> poses);
std::vector<StampedPose> readTrajectory(MapFileReader& reader);

/// `database`: null when the run kept none (relocalisation off).
void writeKeyframes(MapFileWriter& writer, const loop::FernDatabase* database);
/// A database with the saved options (so the same ferns) and keyframes, in their saved order; nullopt when
/// none was saved.
std::optional<loop::FernDatabase> readKeyframes(MapFileReader& reader);

/// Begins the surfels section; the caller then puts header.surfel_count records (putF32s, in chunks) and
/// ends the section.
void beginSurfels(MapFileWriter& writer, const SurfelsHeader& header);
/// Begins the surfels section and reads its counts; the caller then reads surfel_count records (getF32s, in
/// chunks) and ends the section.
SurfelsHeader beginSurfels(MapFileReader& reader);

}  // namespace vifusion::mapfile
