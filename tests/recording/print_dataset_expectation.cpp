// Prints, as JSON on stdout, what a recording of the same sequence must hold, read from a DATASET
// directory (datasets::openDataset("dataset:DIR")), so that tests/node/read_recording.mjs's view of the
// recording (Foxglove's libraries) can be compared with it value by value (tests/node/expect_json.mjs):
//
//   {"calibration": {"fx", "fy", "cx", "cy"}                 the colour camera [px]
//    "frames": [{"t_ns", "index", "depth": {"width", "height", "fnv1a32"}, "rgb": {...}}]
//    "imu": [{"t_ns", "gyro_rad_s": [x, y, z], "accel_mps2": [x, y, z]}]
//    "ground_truth": [{"t_ns", "p_m": [x, y, z], "q_xyzw": [x, y, z, w]}]}    T_world_camera
//
// Stamps are decimal strings (JSON numbers are doubles: 53 bits), doubles are printed with 17 significant
// digits so that they read back as the same double. Depth is hashed as little-endian uint16 rows, colour as
// rgb8 rows (fnv1a.hpp). Usage: print_dataset_expectation DIR

#include <cinttypes>
#include <cstdio>
#include <exception>
#include <memory>
#include <string>

#include "fnv1a.hpp"
#include "vifusion/datasets/dataset_reader.hpp"

namespace vifusion::test {
namespace {

void printStamp(std::int64_t t_ns) { std::printf("\"t_ns\":\"%" PRId64 "\"", t_ns); }

void printTriple(const char* key, double x, double y, double z) {
  std::printf("\"%s\":[%.17g,%.17g,%.17g]", key, x, y, z);
}

void printImage(const char* key, int width, int height, std::uint32_t hash) {
  std::printf("\"%s\":{\"width\":%d,\"height\":%d,\"fnv1a32\":%" PRIu32 "}", key, width, height, hash);
}

int printExpectation(const std::string& dir) {
  const std::unique_ptr<datasets::DatasetReader> reader = datasets::openDataset("dataset:" + dir);
  const PinholeCamera& camera = reader->calibration().camera;
  std::printf("{\"calibration\":{\"fx\":%.17g,\"fy\":%.17g,\"cx\":%.17g,\"cy\":%.17g},\n", camera.fx, camera.fy,
              camera.cx, camera.cy);

  std::printf("\"frames\":[");
  RgbdFrame frame;
  for (bool first = true; reader->nextFrame(frame); first = false) {
    std::printf("%s\n{", first ? "" : ",");
    printStamp(frame.t_ns);
    std::printf(",\"index\":%" PRId64 ",", frame.index);
    printImage("depth", frame.depth.width(), frame.depth.height(), fnv1aOfDepth(frame.depth));
    std::printf(",");
    printImage("rgb", frame.rgb.width(), frame.rgb.height(), fnv1aOfRgb(frame.rgb));
    std::printf("}");
  }

  std::printf("],\n\"imu\":[");
  bool first = true;
  for (const ImuSample& sample : reader->imu()) {
    std::printf("%s\n{", first ? "" : ",");
    printStamp(sample.t_ns);
    std::printf(",");
    printTriple("gyro_rad_s", sample.gyro_rad_s.x(), sample.gyro_rad_s.y(), sample.gyro_rad_s.z());
    std::printf(",");
    printTriple("accel_mps2", sample.accel_mps2.x(), sample.accel_mps2.y(), sample.accel_mps2.z());
    std::printf("}");
    first = false;
  }

  std::printf("],\n\"ground_truth\":[");
  first = true;
  for (const datasets::StampedPose& pose : reader->groundTruth()) {
    const Eigen::Vector3d& p = pose.T_world_body.translation();
    const Eigen::Quaterniond& q = pose.T_world_body.quaternion();
    std::printf("%s\n{", first ? "" : ",");
    printStamp(pose.t_ns);
    std::printf(",");
    printTriple("p_m", p.x(), p.y(), p.z());
    std::printf(",\"q_xyzw\":[%.17g,%.17g,%.17g,%.17g]}", q.x(), q.y(), q.z(), q.w());
    first = false;
  }
  std::printf("]}\n");
  return std::fflush(stdout) == 0 ? 0 : 1;
}

}  // namespace
}  // namespace vifusion::test

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: print_dataset_expectation DATASET_DIR\n");
    return 2;
  }
  try {
    return vifusion::test::printExpectation(argv[1]);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "print_dataset_expectation: %s\n", error.what());
    return 1;
  }
}
