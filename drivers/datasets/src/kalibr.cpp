#include "vifusion/datasets/kalibr.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <initializer_list>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "vifusion/core/error.hpp"
#include "vifusion/core/rig_calibration.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion::datasets {
namespace {

// Kalibr writes rotations with full double precision; 1e-6 accepts any honest file and rejects a
// matrix that is not a rotation (a transposed or hand-edited one).
constexpr double kRotationTolerance = 1e-6;

constexpr std::initializer_list<const char*> kCameraKeys = {
    "T_cam_imu",  "cam_overlaps", "camera_model", "distortion_coeffs", "distortion_model",
    "intrinsics", "resolution",   "rostopic",     "timeshift_cam_imu"};
/// cam1 (the depth camera) has Kalibr's chain transform too.
constexpr std::initializer_list<const char*> kDepthCameraKeys = {
    "T_cam_imu",        "T_cn_cnm1",  "cam_overlaps", "camera_model", "distortion_coeffs",
    "distortion_model", "intrinsics", "resolution",   "rostopic",     "timeshift_cam_imu"};
// cam1's own T_cam_imu, where given, must agree with cam0's composed with T_cn_cnm1 (Kalibr writes all
// three from one solution, so they agree to rounding): 1 mm and 1 mrad catch a chain that belongs to
// another calibration or a hand-edited matrix, far above the rounding.
constexpr double kChainTranslationTolerance_m = 1e-3;
constexpr double kChainRotationTolerance_rad = 1e-3;
constexpr std::initializer_list<const char*> kImuKeys = {
    "accelerometer_noise_density", "accelerometer_random_walk", "gyroscope_noise_density", "gyroscope_random_walk",
    "update_rate", "rostopic", "model", "T_i_b", "time_offset",
    // ours, not Kalibr's: the rest of ImuNoiseParams, so our datasets round-trip
    "gyroscope_saturation", "accelerometer_saturation", "gyroscope_bias_prior", "accelerometer_bias_prior"};
constexpr std::initializer_list<const char*> kDepthNoiseKeys = {
    "disparity_sigma_px", "focal_baseline_px_m",           "quantisation_m", "lateral_sigma_px", "correlation_px",
    "pixels_per_sample",  "inverse_depth_bias_sigma_per_m"};
constexpr std::initializer_list<const char*> kIntensityNoiseKeys = {"sigma", "lateral_sigma_px", "correlation_px",
                                                                    "pixels_per_sample"};

/// One YAML document with the file name, for errors that say "<file> line <n>: ...".
struct Document {
  std::string file;
  YAML::Node root;
};

std::string at(const Document& doc, const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  if (mark.is_null()) return doc.file + ": ";
  return doc.file + " line " + std::to_string(mark.line + 1) + ": ";
}

void requireTopLevelMapping(const Document& doc) {
  if (!doc.root.IsMap()) throw Error(doc.file + ": expected a mapping of keys at the top level");
}

Document parse(const std::string& text, const std::string& name) {
  Document doc{name, {}};
  try {
    doc.root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw Error(doc.file + " line " + std::to_string(e.mark.line + 1) + ": YAML syntax error: " + e.msg);
  }
  requireTopLevelMapping(doc);
  return doc;
}

Document load(const std::filesystem::path& path) {
  Document doc{path.filename().string(), {}};
  std::ifstream in(path);
  if (!in) throw Error(doc.file + ": cannot open file '" + path.string() + "'");
  try {
    doc.root = YAML::Load(in);
  } catch (const YAML::Exception& e) {
    throw Error(doc.file + " line " + std::to_string(e.mark.line + 1) + ": YAML syntax error: " + e.msg);
  }
  requireTopLevelMapping(doc);
  return doc;
}

/// Runs `read` on `doc`; a yaml-cpp exception from a node of an unexpected kind that the checks here did not
/// foresee still becomes an Error naming the file and line, never an exception a caller does not expect.
template <typename Read>
void withYamlErrorsNamed(const Document& doc, Read&& read) {
  try {
    read();
  } catch (const YAML::Exception& e) {
    throw Error(doc.file + (e.mark.is_null() ? std::string() : " line " + std::to_string(e.mark.line + 1)) +
                ": unexpected YAML structure: " + e.msg);
  }
}

std::string joinKeys(std::initializer_list<const char*> keys) {
  std::string joined;
  for (const char* key : keys) joined += (joined.empty() ? "" : ", ") + std::string(key);
  return joined;
}

/// Rejects keys outside `allowed` and repeated keys (yaml-cpp would silently use the first).
void checkKeys(const Document& doc, const YAML::Node& map, std::initializer_list<const char*> allowed,
               const std::string& context) {
  if (!map.IsMap()) throw Error(at(doc, map) + context + " must be a mapping of keys");
  std::set<std::string> seen;
  for (const auto& entry : map) {
    const std::string key = entry.first.Scalar();
    if (std::none_of(allowed.begin(), allowed.end(), [&](const char* k) { return key == k; })) {
      throw Error(at(doc, entry.first) + "unknown key '" + key + "' in " + context +
                  " (expected one of: " + joinKeys(allowed) + ")");
    }
    if (!seen.insert(key).second) throw Error(at(doc, entry.first) + "key '" + key + "' appears twice in " + context);
  }
}

YAML::Node require(const Document& doc, const YAML::Node& map, const char* key) {
  if (!map.IsMap()) throw Error(at(doc, map) + "expected a mapping with key '" + key + "'");
  const YAML::Node node = map[key];
  if (!node) throw Error(at(doc, map) + "missing key '" + key + "'");
  return node;
}

double toDouble(const Document& doc, const YAML::Node& node, const std::string& key) {
  double value = 0.0;
  if (!node.IsScalar() || !YAML::convert<double>::decode(node, value) || !std::isfinite(value)) {
    throw Error(at(doc, node) + "'" + key + "' is not a finite number: '" + (node.IsScalar() ? node.Scalar() : "?") +
                "'");
  }
  return value;
}

/// A flow or block sequence of exactly `size` finite numbers.
std::vector<double> toDoubles(const Document& doc, const YAML::Node& node, const std::string& key, std::size_t size) {
  if (!node.IsSequence() || node.size() != size) {
    throw Error(at(doc, node) + "'" + key + "' must be a list of " + std::to_string(size) + " numbers");
  }
  std::vector<double> values;
  for (std::size_t k = 0; k < size; ++k) values.push_back(toDouble(doc, node[k], key + "[" + std::to_string(k) + "]"));
  return values;
}

Eigen::Vector3d toVector3(const Document& doc, const YAML::Node& node, const std::string& key) {
  const std::vector<double> v = toDoubles(doc, node, key, 3);
  return {v[0], v[1], v[2]};
}

Eigen::Matrix4d toMatrix4(const Document& doc, const YAML::Node& node, const std::string& key) {
  if (!node.IsSequence() || node.size() != 4)
    throw Error(at(doc, node) + "'" + key + "' must be a 4x4 matrix (4 rows)");
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r) {
    const std::vector<double> row = toDoubles(doc, node[r], key + " row " + std::to_string(r + 1), 4);
    for (int c = 0; c < 4; ++c) m(r, c) = row[static_cast<std::size_t>(c)];
  }
  return m;
}

/// A rigid transform from a homogeneous 4×4 matrix, refusing anything that is not one.
SE3d toRigid(const Document& doc, const YAML::Node& node, const std::string& key) {
  const Eigen::Matrix4d m = toMatrix4(doc, node, key);
  const Eigen::Matrix3d R = m.topLeftCorner<3, 3>();
  if ((m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-12) {
    throw Error(at(doc, node) + "'" + key + "' bottom row must be [0, 0, 0, 1]");
  }
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > kRotationTolerance ||
      R.determinant() <= 0.0) {
    throw Error(at(doc, node) + "'" + key + "' rotation block is not a rotation matrix");
  }
  return SE3d(Eigen::Quaterniond(R), m.topRightCorner<3, 1>());
}

PinholeCamera readPinhole(const Document& doc, const YAML::Node& cam, const char* name,
                          std::initializer_list<const char*> keys) {
  if (!cam.IsMap()) throw Error(at(doc, cam) + "'" + name + "' must be a mapping");
  checkKeys(doc, cam, keys, name);
  const YAML::Node model = require(doc, cam, "camera_model");
  if (model.Scalar() != "pinhole") {
    throw Error(at(doc, model) + "camera_model '" + model.Scalar() + "' is not supported (only 'pinhole')");
  }
  if (const YAML::Node coeffs = cam["distortion_coeffs"]) {
    if (!coeffs.IsSequence()) throw Error(at(doc, coeffs) + "'distortion_coeffs' must be a list of numbers");
    for (std::size_t k = 0; k < coeffs.size(); ++k) {
      // The pipeline projects with an undistorted pinhole; non-zero coefficients mean the images
      // need rectifying first, and ignoring them would bias every depth pixel's bearing.
      if (toDouble(doc, coeffs[k], "distortion_coeffs") != 0.0) {
        throw Error(at(doc, coeffs) + "'distortion_coeffs' must be zero: vifusion expects rectified images");
      }
    }
  }
  const YAML::Node intrinsics_node = require(doc, cam, "intrinsics");
  const std::vector<double> intrinsics = toDoubles(doc, intrinsics_node, "intrinsics", 4);
  const YAML::Node resolution_node = require(doc, cam, "resolution");
  const std::vector<double> resolution = toDoubles(doc, resolution_node, "resolution", 2);
  for (const double size : resolution) {
    if (size < 1.0 || size > 65536.0 || size != std::floor(size)) {
      throw Error(at(doc, resolution_node) + "'resolution' must be two positive whole numbers [width, height]");
    }
  }
  try {
    return PinholeCamera::create(static_cast<int>(resolution[0]), static_cast<int>(resolution[1]), intrinsics[0],
                                 intrinsics[1], intrinsics[2], intrinsics[3]);
  } catch (const std::invalid_argument& e) {
    throw Error(at(doc, intrinsics_node) + "invalid 'intrinsics': " + e.what());
  }
}

void readCamera(const Document& doc, const YAML::Node& cam, RigCalibration& calibration) {
  calibration.camera = readPinhole(doc, cam, "cam0", kCameraKeys);
  // Kalibr's T_cam_imu is T_C_S; we keep camera → IMU.
  calibration.T_S_C = toRigid(doc, require(doc, cam, "T_cam_imu"), "T_cam_imu").inverse();
  if (const YAML::Node shift = cam["timeshift_cam_imu"]) {
    const double shift_s = toDouble(doc, shift, "timeshift_cam_imu");
    if (std::abs(shift_s) > 1e6) throw Error(at(doc, shift) + "'timeshift_cam_imu' is out of range: " + shift.Scalar());
    calibration.time_shift_cam_imu_ns = secondsToNs(shift_s);
  }
}

/// cam1, the depth camera. Kalibr's T_cn_cnm1 maps cam0 points into cam1: p_D = T_cn_cnm1 · p_C, i.e. T_D_C.
void readDepthCamera(const Document& doc, const YAML::Node& cam, RigCalibration& calibration) {
  DepthCameraCalibration depth;
  depth.camera = readPinhole(doc, cam, "cam1", kDepthCameraKeys);
  const SE3d T_D_C = toRigid(doc, require(doc, cam, "T_cn_cnm1"), "T_cn_cnm1");
  depth.T_C_D = T_D_C.inverse();
  if (const YAML::Node node = cam["T_cam_imu"]) {
    const SE3d T_D_S = toRigid(doc, node, "T_cam_imu");
    const SE3d chained = T_D_C * calibration.T_S_C.inverse();
    const Eigen::Matrix<double, 6, 1> mismatch = (chained.inverse() * T_D_S).log();
    if (mismatch.head<3>().norm() > kChainTranslationTolerance_m ||
        mismatch.tail<3>().norm() > kChainRotationTolerance_rad) {
      char text[160];
      std::snprintf(text, sizeof(text),
                    "cam1 'T_cam_imu' disagrees with cam0's 'T_cam_imu' and 'T_cn_cnm1' by %.1f mm and %.2f mrad",
                    mismatch.head<3>().norm() * 1e3, mismatch.tail<3>().norm() * 1e3);
      throw Error(at(doc, node) + text);
    }
  }
  calibration.depth_camera = depth;
}

void readImu(const Document& doc, const YAML::Node& imu, const std::string& context, RigCalibration& calibration) {
  if (!imu.IsMap()) throw Error(at(doc, imu) + "'" + context + "' must be a mapping");
  checkKeys(doc, imu, kImuKeys, context);
  ImuNoiseParams& p = calibration.imu;
  const auto set = [&](const char* key, double& value, bool required) {
    const YAML::Node node = imu[key];
    if (node) {
      value = toDouble(doc, node, key);
    } else if (required) {
      throw Error(at(doc, imu) + "missing key '" + key + "' in " + context);
    }
  };
  set("accelerometer_noise_density", p.accel_noise_density, true);
  set("accelerometer_random_walk", p.accel_random_walk, true);
  set("gyroscope_noise_density", p.gyro_noise_density, true);
  set("gyroscope_random_walk", p.gyro_random_walk, true);
  set("update_rate", p.rate_hz, true);
  set("gyroscope_saturation", p.gyro_saturation_rad_s, false);
  set("accelerometer_saturation", p.accel_saturation_mps2, false);
  set("gyroscope_bias_prior", p.gyro_bias_prior, false);
  set("accelerometer_bias_prior", p.accel_bias_prior, false);
  // Kalibr's output for the reference IMU: model 'calibrated', T_i_b identity, time_offset 0. Anything
  // else describes a second IMU or a scale/misalignment model we do not apply.
  if (const YAML::Node model = imu["model"]; model && model.Scalar() != "calibrated") {
    throw Error(at(doc, model) + "IMU model '" + model.Scalar() + "' is not supported (only 'calibrated')");
  }
  if (const YAML::Node T_i_b = imu["T_i_b"]; T_i_b && !toMatrix4(doc, T_i_b, "T_i_b").isIdentity(1e-12)) {
    throw Error(at(doc, T_i_b) + "'T_i_b' must be the identity (only the reference IMU is supported)");
  }
  if (const YAML::Node offset = imu["time_offset"]; offset && toDouble(doc, offset, "time_offset") != 0.0) {
    throw Error(at(doc, offset) + "'time_offset' must be 0 (only the reference IMU is supported)");
  }
  try {
    p.validate();
  } catch (const Error& e) {
    throw Error(at(doc, imu) + e.what());
  }
}

}  // namespace

RigCalibration readKalibr(const std::filesystem::path& camchain_imucam_yaml, const std::filesystem::path& imu_yaml) {
  RigCalibration calibration;
  const Document camchain = load(camchain_imucam_yaml);
  withYamlErrorsNamed(camchain, [&] {
    checkKeys(camchain, camchain.root, {"cam0", "cam1"}, "the camera chain (cam0 colour, cam1 depth)");
    readCamera(camchain, require(camchain, camchain.root, "cam0"), calibration);
    if (const YAML::Node cam1 = camchain.root["cam1"]) readDepthCamera(camchain, cam1, calibration);
  });

  const Document imu = load(imu_yaml);
  withYamlErrorsNamed(imu, [&] {
    if (imu.root["imu0"]) {
      checkKeys(imu, imu.root, {"imu0"}, "the IMU file (one IMU, imu0)");
      readImu(imu, imu.root["imu0"], "imu0", calibration);
    } else {
      readImu(imu, imu.root, "the IMU file", calibration);
    }
  });
  return calibration;
}

namespace {

/// `key` of `map` as a number in [min, max], or `fallback` when the key is absent and `required` is false.
double readBounded(const Document& doc, const YAML::Node& map, const char* context, const char* key, double min,
                   double max, bool required, double fallback) {
  const YAML::Node node = map[key];
  if (!node) {
    if (required) throw Error(at(doc, map) + "missing key '" + key + "' in " + context);
    return fallback;
  }
  const double value = toDouble(doc, node, key);
  if (!(value >= min && value <= max)) {
    throw Error(at(doc, node) + "'" + key + "' in " + context + " must be in [" + std::to_string(min) + ", " +
                std::to_string(max) + "], got " + node.Scalar());
  }
  return value;
}

/// depth_noise: and intensity_noise: (core/camera_noise_model.hpp), written together by `vifusion calib noise`.
/// Bounds: a positive f·b; σ_d ≤ 10 px, q ≤ 0.1 m and σ_I ≤ 255 are far beyond any working sensor (a
/// larger value is a unit mix-up); lateral σ ≤ 10 px; correlation within a 64-pixel window; the bias's σ within
/// the bound on the bias itself.
CameraNoiseModel readNoise(const Document& doc, const YAML::Node& depth_map, const YAML::Node& intensity_map) {
  constexpr double kMaxDisparitySigma_px = 10.0;
  constexpr double kMaxQuantisation_m = 0.1;
  constexpr double kMaxGrey = 255.0;
  constexpr double kMaxCorrelation_px = 64.0;
  constexpr double kMaxLateralSigma_px = 10.0;
  constexpr double kMaxPixelsPerSample = (2 * kMaxCorrelation_px + 1) * (2 * kMaxCorrelation_px + 1);
  constexpr double kMaxFocalBaseline_px_m = 1e4;
  checkKeys(doc, depth_map, kDepthNoiseKeys, "depth_noise");
  checkKeys(doc, intensity_map, kIntensityNoiseKeys, "intensity_noise");
  CameraNoiseModel noise;
  const char* depth = "depth_noise";
  noise.depth.disparity_sigma_px =
      readBounded(doc, depth_map, depth, "disparity_sigma_px", 0.0, kMaxDisparitySigma_px, true, 0.0);
  noise.depth.focal_baseline_px_m =
      readBounded(doc, depth_map, depth, "focal_baseline_px_m", 1e-6, kMaxFocalBaseline_px_m, true, 0.0);
  noise.depth.quantisation_m =
      readBounded(doc, depth_map, depth, "quantisation_m", 0.0, kMaxQuantisation_m, false, 0.0);
  noise.depth.lateral_sigma_px =
      readBounded(doc, depth_map, depth, "lateral_sigma_px", 0.0, kMaxLateralSigma_px, false, 0.0);
  noise.depth.correlation_px =
      readBounded(doc, depth_map, depth, "correlation_px", 0.0, kMaxCorrelation_px, false, 0.0);
  noise.depth.pixels_per_sample =
      readBounded(doc, depth_map, depth, "pixels_per_sample", 1.0, kMaxPixelsPerSample, false, 1.0);
  noise.depth.inverse_depth_bias_sigma_per_m =
      readBounded(doc, depth_map, depth, "inverse_depth_bias_sigma_per_m", 0.0, kMaxInverseDepthBias_per_m, false, 0.0);
  const char* intensity = "intensity_noise";
  noise.intensity.sigma = readBounded(doc, intensity_map, intensity, "sigma", 0.0, kMaxGrey, true, 0.0);
  noise.intensity.lateral_sigma_px =
      readBounded(doc, intensity_map, intensity, "lateral_sigma_px", 0.0, kMaxLateralSigma_px, false, 0.0);
  noise.intensity.correlation_px =
      readBounded(doc, intensity_map, intensity, "correlation_px", 0.0, kMaxCorrelation_px, false, 0.0);
  noise.intensity.pixels_per_sample =
      readBounded(doc, intensity_map, intensity, "pixels_per_sample", 1.0, kMaxPixelsPerSample, false, 1.0);
  return noise;
}

RigCalibration readCalibrationDocument(const Document& doc) {
  RigCalibration calibration;
  checkKeys(doc, doc.root,
            {"cam0", "cam1", "imu0", "depth_scale_m", "inverse_depth_bias_per_m", "gravity_world", "static_accel_bias",
             "depth_noise", "intensity_noise"},
            "the top level");
  readCamera(doc, require(doc, doc.root, "cam0"), calibration);
  if (const YAML::Node cam1 = doc.root["cam1"]) readDepthCamera(doc, cam1, calibration);
  readImu(doc, require(doc, doc.root, "imu0"), "imu0", calibration);
  if (const YAML::Node scale = doc.root["depth_scale_m"]) {
    calibration.depth_scale_m = toDouble(doc, scale, "depth_scale_m");
    if (calibration.depth_scale_m <= 0.0) throw Error(at(doc, scale) + "'depth_scale_m' must be > 0");
  }
  static_assert(kMaxInverseDepthBias_per_m == 0.1, "the message below quotes the bound");
  if (const YAML::Node bias = doc.root["inverse_depth_bias_per_m"]) {
    calibration.inverse_depth_bias_per_m = toDouble(doc, bias, "inverse_depth_bias_per_m");
    if (!(std::abs(calibration.inverse_depth_bias_per_m) <= kMaxInverseDepthBias_per_m)) {
      throw Error(at(doc, bias) + "'inverse_depth_bias_per_m' (1/z_raw − 1/z) must be within ±0.1 1/m, got " +
                  bias.Scalar());
    }
  }
  if (const YAML::Node gravity = doc.root["gravity_world"]) {
    calibration.g_W = toVector3(doc, gravity, "gravity_world");
    if (calibration.g_W.norm() < 1.0)
      throw Error(at(doc, gravity) + "'gravity_world' must have a magnitude near 9.81 m/s²");
    calibration.imu.gravity_mps2 = calibration.g_W.norm();
  }
  if (const YAML::Node bias = doc.root["static_accel_bias"]) {
    calibration.imu.static_accel_bias_mps2 = toVector3(doc, bias, "static_accel_bias");
  }
  const YAML::Node depth_noise = doc.root["depth_noise"];
  const YAML::Node intensity_noise = doc.root["intensity_noise"];
  if (depth_noise || intensity_noise) {
    if (!depth_noise || !intensity_noise || !depth_noise.IsMap() || !intensity_noise.IsMap()) {
      throw Error(at(doc, depth_noise ? depth_noise : intensity_noise) +
                  "'depth_noise' and 'intensity_noise' must both be mappings (vifusion calib noise writes both)");
    }
    calibration.noise = readNoise(doc, depth_noise, intensity_noise);
  }
  return calibration;
}

}  // namespace

RigCalibration readCalibrationYaml(const std::filesystem::path& path) {
  const Document doc = load(path);
  RigCalibration calibration;
  withYamlErrorsNamed(doc, [&] { calibration = readCalibrationDocument(doc); });
  return calibration;
}

RigCalibration readCalibrationYamlText(const std::string& text, const std::string& name) {
  const Document doc = parse(text, name);
  RigCalibration calibration;
  withYamlErrorsNamed(doc, [&] { calibration = readCalibrationDocument(doc); });
  return calibration;
}

std::string calibrationYamlText(const RigCalibration& calibration) {
  const auto vector = [](YAML::Emitter& out, std::initializer_list<double> values) {
    out << YAML::Flow << YAML::BeginSeq;
    for (const double v : values) out << v;
    out << YAML::EndSeq;
  };
  const auto matrix = [&](YAML::Emitter& out, const char* key, const char* comment, const SE3d& T) {
    const Eigen::Matrix4d m = T.matrix();
    out << YAML::Key << key << YAML::Comment(comment) << YAML::Value << YAML::BeginSeq;
    for (int r = 0; r < 4; ++r) vector(out, {m(r, 0), m(r, 1), m(r, 2), m(r, 3)});
    out << YAML::EndSeq;
  };
  const auto pinhole = [&](YAML::Emitter& out, const PinholeCamera& camera) {
    out << YAML::Key << "camera_model" << YAML::Value << "pinhole";
    out << YAML::Key << "distortion_model" << YAML::Value << "none";
    out << YAML::Key << "distortion_coeffs" << YAML::Value << YAML::Flow << YAML::BeginSeq << YAML::EndSeq;
    out << YAML::Key << "intrinsics" << YAML::Value;
    vector(out, {camera.fx, camera.fy, camera.cx, camera.cy});
    out << YAML::Key << "resolution" << YAML::Value << YAML::Flow << YAML::BeginSeq << camera.width << camera.height
        << YAML::EndSeq;
    out << YAML::Key << "timeshift_cam_imu" << YAML::Value << nsToSeconds(calibration.time_shift_cam_imu_ns);
  };
  const ImuNoiseParams& imu = calibration.imu;
  const SE3d T_C_S = calibration.T_S_C.inverse();

  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap << YAML::Key << "cam0" << YAML::Value << YAML::BeginMap;
  matrix(out, "T_cam_imu", "Kalibr convention: T_C_S, p_C = T_cam_imu * p_S", T_C_S);
  pinhole(out, calibration.camera);
  out << YAML::EndMap;
  if (calibration.depth_camera) {
    const SE3d T_D_C = calibration.depth_camera->T_C_D.inverse();
    out << YAML::Key << "cam1" << YAML::Value << YAML::BeginMap;
    matrix(out, "T_cam_imu", "the depth camera's T_D_S", T_D_C * T_C_S);
    matrix(out, "T_cn_cnm1", "Kalibr convention: T_D_C, p_D = T_cn_cnm1 * p_C", T_D_C);
    pinhole(out, calibration.depth_camera->camera);
    out << YAML::EndMap;
  }

  out << YAML::Key << "imu0" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "accelerometer_noise_density" << YAML::Value << imu.accel_noise_density;
  out << YAML::Key << "accelerometer_random_walk" << YAML::Value << imu.accel_random_walk;
  out << YAML::Key << "gyroscope_noise_density" << YAML::Value << imu.gyro_noise_density;
  out << YAML::Key << "gyroscope_random_walk" << YAML::Value << imu.gyro_random_walk;
  out << YAML::Key << "update_rate" << YAML::Value << imu.rate_hz;
  out << YAML::Key << "gyroscope_saturation" << YAML::Value << imu.gyro_saturation_rad_s;
  out << YAML::Key << "accelerometer_saturation" << YAML::Value << imu.accel_saturation_mps2;
  out << YAML::Key << "gyroscope_bias_prior" << YAML::Value << imu.gyro_bias_prior;
  out << YAML::Key << "accelerometer_bias_prior" << YAML::Value << imu.accel_bias_prior;
  out << YAML::EndMap;

  out << YAML::Key << "depth_scale_m" << YAML::Value << calibration.depth_scale_m;
  out << YAML::Key << "inverse_depth_bias_per_m" << YAML::Value << calibration.inverse_depth_bias_per_m;
  out << YAML::Key << "gravity_world" << YAML::Value;
  vector(out, {calibration.g_W.x(), calibration.g_W.y(), calibration.g_W.z()});
  out << YAML::Key << "static_accel_bias" << YAML::Value;
  const Eigen::Vector3d& bias = imu.static_accel_bias_mps2;
  vector(out, {bias.x(), bias.y(), bias.z()});
  if (calibration.noise) {
    const DepthNoiseModel& depth = calibration.noise->depth;
    out << YAML::Key << "depth_noise" << YAML::Comment("1/z noise = disparity_sigma_px / focal_baseline_px_m")
        << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "disparity_sigma_px" << YAML::Value << depth.disparity_sigma_px;
    out << YAML::Key << "focal_baseline_px_m" << YAML::Value << depth.focal_baseline_px_m;
    out << YAML::Key << "quantisation_m" << YAML::Value << depth.quantisation_m;
    out << YAML::Key << "lateral_sigma_px" << YAML::Value << depth.lateral_sigma_px;
    out << YAML::Key << "correlation_px" << YAML::Value << depth.correlation_px;
    out << YAML::Key << "pixels_per_sample" << YAML::Value << depth.pixels_per_sample;
    out << YAML::Key << "inverse_depth_bias_sigma_per_m" << YAML::Value << depth.inverse_depth_bias_sigma_per_m;
    out << YAML::EndMap;
    const IntensityNoiseModel& intensity = calibration.noise->intensity;
    out << YAML::Key << "intensity_noise" << YAML::Comment("grey level, 0-255 scale") << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "sigma" << YAML::Value << intensity.sigma;
    out << YAML::Key << "lateral_sigma_px" << YAML::Value << intensity.lateral_sigma_px;
    out << YAML::Key << "correlation_px" << YAML::Value << intensity.correlation_px;
    out << YAML::Key << "pixels_per_sample" << YAML::Value << intensity.pixels_per_sample;
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
  if (!out.good()) throw Error("cannot format calibration: " + out.GetLastError());

  return std::string(out.c_str()) + "\n";
}

void writeCalibrationYaml(const std::filesystem::path& path, const RigCalibration& calibration) {
  const std::string text = calibrationYamlText(calibration);
  std::ofstream file(path);
  if (!file) throw Error("cannot create '" + path.string() + "'");
  file << text;
  if (!file.flush()) throw Error("cannot write '" + path.string() + "'");
}

}  // namespace vifusion::datasets
