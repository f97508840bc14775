#include "vifusion/mapfile/map_sections.hpp"

#include <cmath>

#include "vifusion/core/error.hpp"

namespace vifusion::mapfile {
namespace {

/// Bytes of one pose: 7 f64.
constexpr std::uint64_t kPoseBytes = 7 * 8;
constexpr std::uint64_t kStampedPoseBytes = 8 + kPoseBytes;
constexpr std::uint64_t kSurfelBytes = kSurfelFloats * 4;

void putString(MapFileWriter& writer, const std::string& text) {
  writer.putU32(static_cast<std::uint32_t>(text.size()));
  writer.putBytes({reinterpret_cast<const std::uint8_t*>(text.data()), text.size()});
}

void putVector3(MapFileWriter& writer, const Eigen::Vector3d& v) {
  for (int i = 0; i < 3; ++i) writer.putF64(v[i]);
}

void putQuaternion(MapFileWriter& writer, const Eigen::Quaterniond& q) {
  writer.putF64(q.x());
  writer.putF64(q.y());
  writer.putF64(q.z());
  writer.putF64(q.w());
}

void putPose(MapFileWriter& writer, const SE3d& T) {
  putQuaternion(writer, T.quaternion());
  putVector3(writer, T.translation());
}

void putCamera(MapFileWriter& writer, const PinholeCamera& camera) {
  writer.putI32(camera.width);
  writer.putI32(camera.height);
  writer.putF64(camera.fx);
  writer.putF64(camera.fy);
  writer.putF64(camera.cx);
  writer.putF64(camera.cy);
}

/// A finite f64; `what` names the field in the error.
double getFinite(MapFileReader& reader, const char* what) {
  const double value = reader.getF64();
  if (!std::isfinite(value)) reader.fail(std::string(what) + " is not finite");
  return value;
}

Eigen::Vector3d getVector3(MapFileReader& reader, const char* what) {
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) v[i] = getFinite(reader, what);
  return v;
}

/// A unit quaternion as stored (to within what normalising it would change by rounding).
Eigen::Quaterniond getQuaternion(MapFileReader& reader, const char* what) {
  const double x = getFinite(reader, what), y = getFinite(reader, what), z = getFinite(reader, what),
               w = getFinite(reader, what);
  const Eigen::Quaterniond q(w, x, y, z);
  constexpr double kUnitTolerance = 1e-6;  // a saved quaternion is normalised; far more than rounding is corruption
  if (std::abs(q.norm() - 1.0) > kUnitTolerance) reader.fail(std::string(what) + " is not a unit quaternion");
  return q;
}

SE3d getPose(MapFileReader& reader, const char* what) {
  const Eigen::Quaterniond q = getQuaternion(reader, what);
  const Eigen::Vector3d t = getVector3(reader, what);
  return SE3d::fromUnitQuaternion(q, t);
}

PinholeCamera getCamera(MapFileReader& reader) {
  const int width = reader.getI32(), height = reader.getI32();
  const double fx = reader.getF64(), fy = reader.getF64(), cx = reader.getF64(), cy = reader.getF64();
  try {
    return PinholeCamera::create(width, height, fx, fy, cx, cy);
  } catch (const Error& error) {
    reader.fail(error.what());
  }
}

/// `count` records of `record_bytes` must be exactly the section's remaining payload.
void expectRecords(MapFileReader& reader, std::uint64_t count, std::uint64_t record_bytes, const char* what) {
  if (count > reader.remaining() / record_bytes || count * record_bytes != reader.remaining())
    reader.fail(std::to_string(count) + " " + what + " of " + std::to_string(record_bytes) + " bytes, but " +
                std::to_string(reader.remaining()) + " bytes follow");
}

}  // namespace

void writeMeta(MapFileWriter& writer, const MapMeta& meta) {
  writer.beginSection(MapSection::kMeta);
  putString(writer, meta.mode);
  writer.putU32(meta.frames);
  writer.putI64(meta.first_t_ns);
  writer.putI64(meta.last_t_ns);
  writer.endSection();
}

MapMeta readMeta(MapFileReader& reader) {
  reader.beginSection(MapSection::kMeta);
  MapMeta meta;
  const std::uint32_t length = reader.getU32();
  if (length > kMaxModeNameBytes) reader.fail("mode name of " + std::to_string(length) + " bytes");
  meta.mode.resize(length);
  reader.getBytes({reinterpret_cast<std::uint8_t*>(meta.mode.data()), meta.mode.size()});
  meta.frames = reader.getU32();
  meta.first_t_ns = reader.getI64();
  meta.last_t_ns = reader.getI64();
  if (meta.last_t_ns < meta.first_t_ns) reader.fail("its last frame is older than its first");
  reader.endSection();
  return meta;
}

void writeCalibration(MapFileWriter& writer, const RigCalibration& calibration) {
  writer.beginSection(MapSection::kCalibration);
  putCamera(writer, calibration.camera);
  writer.putU8(calibration.depth_camera ? 1 : 0);
  if (calibration.depth_camera) {
    putCamera(writer, calibration.depth_camera->camera);
    putPose(writer, calibration.depth_camera->T_C_D);
  }
  writer.putF64(calibration.depth_scale_m);
  writer.putF64(calibration.inverse_depth_bias_per_m);
  putPose(writer, calibration.T_S_C);
  writer.putI64(calibration.time_shift_cam_imu_ns);
  const ImuNoiseParams& imu = calibration.imu;
  for (const double value : {imu.gyro_saturation_rad_s, imu.accel_saturation_mps2, imu.gyro_noise_density,
                             imu.accel_noise_density, imu.gyro_bias_prior, imu.accel_bias_prior, imu.gyro_random_walk,
                             imu.accel_random_walk, imu.gravity_mps2, imu.rate_hz})
    writer.putF64(value);
  putVector3(writer, imu.static_accel_bias_mps2);
  putVector3(writer, calibration.g_W);
  writer.endSection();
}

RigCalibration readCalibration(MapFileReader& reader) {
  reader.beginSection(MapSection::kCalibration);
  RigCalibration calibration;
  calibration.camera = getCamera(reader);
  const std::uint8_t has_depth_camera = reader.getU8();
  if (has_depth_camera > 1) reader.fail("depth camera flag " + std::to_string(has_depth_camera) + " (0 or 1)");
  if (has_depth_camera == 1) {
    DepthCameraCalibration depth;
    depth.camera = getCamera(reader);
    depth.T_C_D = getPose(reader, "T_C_D");
    calibration.depth_camera = depth;
  }
  calibration.depth_scale_m = getFinite(reader, "depth_scale_m");
  if (!(calibration.depth_scale_m > 0.0)) reader.fail("depth_scale_m is not positive");
  calibration.inverse_depth_bias_per_m = getFinite(reader, "inverse_depth_bias_per_m");
  if (std::abs(calibration.inverse_depth_bias_per_m) > kMaxInverseDepthBias_per_m)
    reader.fail("inverse_depth_bias_per_m is beyond any working sensor");
  calibration.T_S_C = getPose(reader, "T_S_C");
  calibration.time_shift_cam_imu_ns = reader.getI64();
  ImuNoiseParams& imu = calibration.imu;
  for (double* value : {&imu.gyro_saturation_rad_s, &imu.accel_saturation_mps2, &imu.gyro_noise_density,
                        &imu.accel_noise_density, &imu.gyro_bias_prior, &imu.accel_bias_prior, &imu.gyro_random_walk,
                        &imu.accel_random_walk, &imu.gravity_mps2, &imu.rate_hz})
    *value = reader.getF64();
  imu.static_accel_bias_mps2 = getVector3(reader, "static_accel_bias_mps2");
  try {
    imu.validate();
  } catch (const Error& error) {
    reader.fail(error.what());
  }
  calibration.g_W = getVector3(reader, "g_W");
  reader.endSection();
  return calibration;
}

void writeState(MapFileWriter& writer, const std::optional<NavState>& state) {
  writer.beginSection(MapSection::kState);
  writer.putU8(state ? 1 : 0);
  if (state) {
    putVector3(writer, state->r_W_C);
    putQuaternion(writer, state->q_W_C);
    putVector3(writer, state->v_I_S);
    putVector3(writer, state->b_g);
    putVector3(writer, state->b_a);
    putQuaternion(writer, state->q_I_W);
  }
  writer.endSection();
}

std::optional<NavState> readState(MapFileReader& reader) {
  reader.beginSection(MapSection::kState);
  const std::uint8_t present = reader.getU8();
  if (present > 1) reader.fail("presence flag " + std::to_string(present) + " (0 or 1)");
  std::optional<NavState> state;
  if (present == 1) {
    NavState x;
    x.r_W_C = getVector3(reader, "r_W_C");
    x.q_W_C = getQuaternion(reader, "q_W_C");
    x.v_I_S = getVector3(reader, "v_I_S");
    x.b_g = getVector3(reader, "b_g");
    x.b_a = getVector3(reader, "b_a");
    x.q_I_W = getQuaternion(reader, "q_I_W");
    state = x;
  }
  reader.endSection();
  return state;
}

void writeTrajectory(MapFileWriter& writer, std::span<const StampedPose> poses) {
  writer.beginSection(MapSection::kTrajectory);
  writer.putU64(poses.size());
  for (const StampedPose& pose : poses) {
    writer.putI64(pose.t_ns);
    putPose(writer, pose.T_W_C);
  }
  writer.endSection();
}

std::vector<StampedPose> readTrajectory(MapFileReader& reader) {
  reader.beginSection(MapSection::kTrajectory);
  const std::uint64_t count = reader.getU64();
  expectRecords(reader, count, kStampedPoseBytes, "poses");
  std::vector<StampedPose> poses(static_cast<std::size_t>(count));
  for (StampedPose& pose : poses) {
    pose.t_ns = reader.getI64();
    pose.T_W_C = getPose(reader, "a trajectory pose");
  }
  reader.endSection();
  return poses;
}

void writeKeyframes(MapFileWriter& writer, const loop::FernDatabase* saved) {
  writer.beginSection(MapSection::kKeyframes);
  writer.putU8(saved != nullptr ? 1 : 0);
  if (saved == nullptr) {
    writer.endSection();
    return;
  }
  const loop::FernDatabase& database = *saved;
  const loop::FernOptions& options = database.options();
  writer.putI32(options.num_ferns);
  writer.putI32(options.downsample_factor);
  writer.putF32(options.min_depth_m);
  writer.putF32(options.max_depth_m);
  writer.putF64(options.keyframe_threshold);
  writer.putF64(options.min_valid_fraction);
  writer.putI32(options.capacity);
  writer.putU64(options.seed);
  writer.putI32(database.inputWidth());
  writer.putI32(database.inputHeight());
  writer.putU32(static_cast<std::uint32_t>(database.size()));
  for (std::int32_t id = 0; id < database.size(); ++id) {
    const loop::FernKeyframe keyframe = database.keyframe(id);
    putPose(writer, keyframe.T_W_C);
    writer.putI64(keyframe.t_ns);
    writer.putU32(keyframe.frame_index);
    writer.putBytes(keyframe.codes);
    for (int y = 0; y < keyframe.rgb.height; ++y)
      writer.putBytes({reinterpret_cast<const std::uint8_t*>(keyframe.rgb.row(y)),
                       static_cast<std::size_t>(keyframe.rgb.width) * sizeof(Rgb8)});
    for (int y = 0; y < keyframe.depth_m.height; ++y)
      writer.putF32s({keyframe.depth_m.row(y), static_cast<std::size_t>(keyframe.depth_m.width)});
  }
  writer.endSection();
}

std::optional<loop::FernDatabase> readKeyframes(MapFileReader& reader) {
  reader.beginSection(MapSection::kKeyframes);
  const std::uint8_t present = reader.getU8();
  if (present > 1) reader.fail("presence flag " + std::to_string(present) + " (0 or 1)");
  std::optional<loop::FernDatabase> database;
  if (present == 0) {
    reader.endSection();
    return database;
  }
  loop::FernOptions options;
  options.num_ferns = reader.getI32();
  options.downsample_factor = reader.getI32();
  options.min_depth_m = reader.getF32();
  options.max_depth_m = reader.getF32();
  options.keyframe_threshold = reader.getF64();
  options.min_valid_fraction = reader.getF64();
  options.capacity = reader.getI32();
  options.seed = reader.getU64();
  const int input_width = reader.getI32(), input_height = reader.getI32();
  const std::uint32_t count = reader.getU32();
  if (count > static_cast<std::uint32_t>(std::max(options.capacity, 0)))
    reader.fail(std::to_string(count) + " keyframes in a database of capacity " + std::to_string(options.capacity));
  try {
    database.emplace(options, input_width, input_height);
  } catch (const Error& error) {
    reader.fail(error.what());
  }
  loop::FernFrame frame = database->makeFrame();
  const auto pixels =
      static_cast<std::uint64_t>(frame.image.width()) * static_cast<std::uint64_t>(frame.image.height());
  expectRecords(reader, count, kStampedPoseBytes + 4 + static_cast<std::uint64_t>(options.num_ferns) + 7 * pixels,
                "keyframes");
  for (std::uint32_t k = 0; k < count; ++k) {
    const SE3d T_W_C = getPose(reader, "a keyframe pose");
    const std::int64_t t_ns = reader.getI64();
    const std::uint32_t frame_index = reader.getU32();
    for (int fern = 0; fern < options.num_ferns; ++fern) {
      const std::uint8_t code = reader.getU8();
      if (code >= loop::kFernCodeCount && code != loop::kInvalidFernCode)
        reader.fail("keyframe " + std::to_string(k) + " has fern code " + std::to_string(code));
      frame.codes.set(fern, code);
    }
    reader.getBytes({reinterpret_cast<std::uint8_t*>(frame.image.rgb.data()), pixels * sizeof(Rgb8)});
    reader.getF32s({frame.image.depth_m.data(), pixels});
    database->restore(frame, T_W_C, t_ns, frame_index);
  }
  reader.endSection();
  return database;
}

void beginSurfels(MapFileWriter& writer, const SurfelsHeader& header) {
  writer.beginSection(MapSection::kSurfels);
  writer.putU32(header.surfel_count);
  writer.putU32(header.active_begin);
  writer.putU32(header.frame);
}

SurfelsHeader beginSurfels(MapFileReader& reader) {
  reader.beginSection(MapSection::kSurfels);
  SurfelsHeader header;
  header.surfel_count = reader.getU32();
  header.active_begin = reader.getU32();
  header.frame = reader.getU32();
  if (header.active_begin > header.surfel_count)
    reader.fail("active_begin " + std::to_string(header.active_begin) + " beyond its " +
                std::to_string(header.surfel_count) + " surfels");
  expectRecords(reader, header.surfel_count, kSurfelBytes, "surfels");
  return header;
}

}  // namespace vifusion::mapfile
