#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <string>

#include "expect_error.hpp"
#include "temp_file.hpp"
#include "vifusion/eval/ply_points.hpp"
#include "vifusion/eval/reconstruction_error.hpp"

namespace vifusion::eval {
namespace {

using test::expectError;
using test::TempFile;

std::string binaryPly(int vertices, int written) {
  std::string text =
      "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(vertices) +
      "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\n"
      "property uchar blue\nproperty float radius\nend_header\n";
  for (int v = 0; v < written; ++v) {
    const float xyz[3] = {static_cast<float>(v), 0.5f * v, -1.0f};
    const unsigned char rgb[3] = {10, 20, 30};
    const float radius = 0.01f;
    text.append(reinterpret_cast<const char*>(xyz), sizeof(xyz));
    text.append(reinterpret_cast<const char*>(rgb), sizeof(rgb));
    text.append(reinterpret_cast<const char*>(&radius), sizeof(radius));
  }
  return text;
}

TEST(PlyPoints, ReadsBinaryAndAsciiPositionsSkippingOtherProperties) {
  const TempFile binary("map.ply", binaryPly(3, 3));
  const auto points = readPlyPositions(binary.path());
  ASSERT_EQ(points.size(), 3u);
  EXPECT_EQ(points[2], Eigen::Vector3d(2.0, 1.0, -1.0));

  const TempFile ascii("map.ply",
                       "ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\nproperty double y\n"
                       "property double z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n"
                       "1 2 3\n4 5 6\n");
  const auto ascii_points = readPlyPositions(ascii.path());
  ASSERT_EQ(ascii_points.size(), 2u);
  EXPECT_EQ(ascii_points[1], Eigen::Vector3d(4, 5, 6));
}

TEST(PlyPoints, CorruptFilesAreNamed) {
  const TempFile truncated("map.ply", binaryPly(5, 3));
  expectError([&] { readPlyPositions(truncated.path()); },
              "map.ply: the header promises 5 vertices, but only 57 bytes follow it");
  const TempFile truncated_ascii("map.ply",
                                 "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                                 "property float z\nend_header\n1.000000 2.000000 3.000000\n");
  expectError([&] { readPlyPositions(truncated_ascii.path()); }, "map.ply: truncated after 1 of 2 vertices");
  const TempFile not_ply("map.ply", "hello\n");
  expectError([&] { readPlyPositions(not_ply.path()); }, "not a PLY file");
  const TempFile big_endian("map.ply", "ply\nformat binary_big_endian 1.0\nend_header\n");
  expectError([&] { readPlyPositions(big_endian.path()); }, "'binary_big_endian' is not supported");
  const TempFile no_xyz("map.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n1\n");
  expectError([&] { readPlyPositions(no_xyz.path()); }, "no x, y and z");
}

// Found by fuzz_ply_points: a corrupt vertex count was reserved before any vertex was read.
TEST(PlyPoints, VertexCountBeyondTheFileIsRefusedBeforeAnyAllocation) {
  std::string huge = binaryPly(3, 3);
  huge.replace(huge.find("vertex 3"), 8, "vertex 100000000000");
  const TempFile file("map.ply", huge);
  expectError([&] { readPlyPositions(file.path()); },
              "map.ply: the header promises 100000000000 vertices, but only 57 bytes follow it");
  const TempFile negative("map.ply",
                          "ply\nformat ascii 1.0\nelement vertex -1\nproperty float x\nproperty float y\n"
                          "property float z\nend_header\n1 2 3\n");
  expectError([&] { readPlyPositions(negative.path()); }, "map.ply: the header promises 18446744073709551615 vertices");
}

TEST(PlyPoints, NonFinitePositionsAndOtherTypesAndAMissingHeaderEndAreNamed) {
  std::string nan = binaryPly(2, 2);
  const float not_a_number = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(nan.data() + nan.size() - 19 + 4, &not_a_number, sizeof(float));  // vertex 1's y
  const TempFile with_nan("map.ply", nan);
  expectError([&] { readPlyPositions(with_nan.path()); }, "map.ply: vertex 1 has a position that is not finite");
  const TempFile int_positions("map.ply",
                               "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty int x\n"
                               "property int y\nproperty int z\nend_header\n" +
                                   std::string(12, '\0'));
  expectError([&] { readPlyPositions(int_positions.path()); },
              "map.ply: position property of type 'int' (expected float or double)");
  const TempFile no_end("map.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n");
  expectError([&] { readPlyPositions(no_end.path()); }, "map.ply: no end_header line");
}

TEST(ReconstructionError, DistancesAfterAlignmentToAPlane) {
  // Points 1, 2 and 3 cm above the plane y = 0 after the alignment shifts them down by 1 m.
  const std::vector<Eigen::Vector3d> points = {{0, 1.01, 0}, {1, 1.02, 0}, {2, 1.03, 5}};
  const SE3d T_gt_est(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, -1, 0));
  const ReconstructionError error =
      reconstructionError(points, T_gt_est, [](const Eigen::Vector3d& p) { return std::abs(p.y()); });
  EXPECT_NEAR(error.mean_m, 0.02, 1e-12);
  EXPECT_NEAR(error.median_m, 0.02, 1e-12);
  EXPECT_NEAR(error.rms_m, std::sqrt((1e-4 + 4e-4 + 9e-4) / 3.0), 1e-12);
  EXPECT_NEAR(error.within_1cm, 0.0, 1e-12);  // 1.01 − 1 is a hair above 1 cm in binary
  EXPECT_EQ(error.points, 3u);
  expectError([&] { reconstructionError({}, T_gt_est, [](const Eigen::Vector3d&) { return 0.0; }); }, "no points");
}

}  // namespace
}  // namespace vifusion::eval
