// Seeds of the binary readers: map files from the map-file tests' sample map, PLY files of points of a real
// 7-Scenes depth frame (our writer's binary layout and an ASCII one), and one CDR message of every type.

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <tuple>
#include <vector>

#include "../cdr_message_types.hpp"
#include "map_file_fixture.hpp"
#include "sample_messages.hpp"
#include "seed_writer.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/map/surfel_ply.hpp"
#include "vifusion/ros2_msgs/message_io.hpp"

namespace vifusion::fuzz::seeds {
namespace {

constexpr double kSevenScenesFocalPx = 585.0, kSevenScenesCentreU = 320.0, kSevenScenesCentreV = 240.0;
constexpr double kMillimetre = 1e-3;  ///< [m]
constexpr int kPlyGridStep = 80;      ///< every 80th pixel each way: 48 points of the 640×480 frame

std::vector<std::uint8_t> fileBytes(const std::filesystem::path& path) {
  return mapfile::test::readBytes(path.string());
}

/// Surfels at every kPlyGridStep-th valid pixel of frame-000150's depth, in its camera frame.
std::vector<map::Surfel> realSurfels(const std::filesystem::path& data_dir) {
  const std::filesystem::path file = data_dir / "7scenes-50/rgbd-frames/frame-000150.depth.png";
  const cv::Mat depth = cv::imread(file.string(), cv::IMREAD_UNCHANGED);
  if (depth.type() != CV_16UC1) throw Error(file.string() + ": missing or not a 16-bit depth PNG");
  std::vector<map::Surfel> surfels;
  for (int v = kPlyGridStep / 2; v < depth.rows; v += kPlyGridStep) {
    for (int u = kPlyGridStep / 2; u < depth.cols; u += kPlyGridStep) {
      const double z = depth.at<std::uint16_t>(v, u) * kMillimetre;
      if (z <= 0.0) continue;
      map::Surfel surfel;
      surfel.position_confidence << static_cast<float>((u - kSevenScenesCentreU) * z / kSevenScenesFocalPx),
          static_cast<float>((v - kSevenScenesCentreV) * z / kSevenScenesFocalPx), static_cast<float>(z), 10.0f;
      surfel.normal_radius << 0.0f, 0.0f, -1.0f, static_cast<float>(z / kSevenScenesFocalPx);
      surfel.setPackedColour(map::packRgb8(Eigen::Vector3f(200.0f, 150.0f, 100.0f)));
      surfels.push_back(surfel);
    }
  }
  return surfels;
}

std::string asciiPly(const std::vector<map::Surfel>& surfels) {
  std::ostringstream out;
  out << "ply\nformat ascii 1.0\ncomment points of 7-Scenes frame-000150\nelement vertex " << surfels.size()
      << "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nelement face 0\n"
      << "property list uchar int vertex_indices\nend_header\n";
  for (const map::Surfel& surfel : surfels) {
    out << surfel.position_confidence.x() << " " << surfel.position_confidence.y() << " "
        << surfel.position_confidence.z() << " 200\n";
  }
  return out.str();
}

template <typename Message>
void writeCdrSeed(SeedWriter& seeds, const std::string& name, const Message& message) {
  std::vector<std::uint8_t> bytes(ros2_msgs::serializedSize(message));
  if (!ros2_msgs::serializeMessage(message, bytes).ok()) throw Error(name + ": the sample message does not serialise");
  seeds.write(name, static_cast<std::uint8_t>(cdrTypeIndex<Message>()), bytes);
}

}  // namespace

void writeMapFileSeeds(const std::filesystem::path& root) {
  SeedWriter seeds(root, "fuzz_map_file");
  const std::filesystem::path scratch = root / "scratch.map";
  // Small enough to fuzz quickly: a few poses and surfels; one without keyframes (relocalisation off), one
  // with them.
  for (const bool with_keyframes : {false, true}) {
    mapfile::test::SampleMap map(with_keyframes ? 2 : 1, 24);
    map.trajectory.resize(3);
    if (!with_keyframes) {
      map.keyframes.reset();
      map.state.reset();
    }
    mapfile::test::writeSampleMap(map, scratch.string());
    seeds.write(with_keyframes ? "with_keyframes.map" : "small.map", std::nullopt, fileBytes(scratch));
  }
  std::filesystem::remove(scratch);
}

void writePlySeeds(const std::filesystem::path& root, const std::filesystem::path& data_dir) {
  SeedWriter seeds(root, "fuzz_ply_points");
  const std::vector<map::Surfel> surfels = realSurfels(data_dir);
  const std::filesystem::path scratch = root / "scratch.ply";
  map::writeSurfelPly(scratch, surfels);
  seeds.write("surfels_binary.ply", std::nullopt, fileBytes(scratch));
  std::filesystem::remove(scratch);
  seeds.write("points_ascii.ply", std::nullopt, asciiPly(surfels));
}

void writeCdrSeeds(const std::filesystem::path& root) {
  SeedWriter seeds(root, "fuzz_cdr_messages");
  const ros2_msgs::test::SampleMessages sample;
  writeCdrSeed(seeds, "time", sample.time);
  writeCdrSeed(seeds, "header", sample.header);
  writeCdrSeed(seeds, "image_depth", sample.depth);
  writeCdrSeed(seeds, "image_rgb", sample.rgb);
  writeCdrSeed(seeds, "image_yuyv", sample.yuyv);
  writeCdrSeed(seeds, "imu", sample.imu);
  writeCdrSeed(seeds, "roi", sample.camera_info_plumb_bob.roi);
  writeCdrSeed(seeds, "camera_info_plumb_bob", sample.camera_info_plumb_bob);
  writeCdrSeed(seeds, "camera_info_equidistant", sample.camera_info_equidistant);
  writeCdrSeed(seeds, "vector3", sample.transform.transform.translation);
  writeCdrSeed(seeds, "quaternion", sample.transform.transform.rotation);
  writeCdrSeed(seeds, "transform", sample.transform.transform);
  writeCdrSeed(seeds, "transform_stamped", sample.transform);
  writeCdrSeed(seeds, "tf_static", sample.tf_static);
  writeCdrSeed(seeds, "frame_stamps", sample.frame_stamps);
  writeCdrSeed(seeds, "motion_packet", sample.motion_packet);
  writeCdrSeed(seeds, "sync_edge", sample.sync_edge);
  writeCdrSeed(seeds, "clock_mapping", sample.clock_mapping);
  writeCdrSeed(seeds, "recording_info", sample.recording_info);
}

}  // namespace vifusion::fuzz::seeds
